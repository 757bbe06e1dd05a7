#version 460
// Per-face setup of the GPU shadow volume (volume.glsl): VolumeBuilder::make of
// shadows/wedges/shadow_volume.cpp in double — the face's screen polygon (clip.glsl), the cull,
// the orientation from the determinant of its first three directions, the planes through the
// camera containing each edge (computed from the edge's vertex ids in canonical order, so the two
// faces sharing an edge use exactly opposite planes: watertight counts) and the tie-rule bits.
#include "common.glsl"
#include "clip.glsl"
#include "volume.glsl"

layout(buffer_reference, scalar) buffer View {
  ClipView clip;
  dvec3 light;
  double near, guard, margin;
  double grow;  // candidate rectangle growth, pixels (shadow_volume_vk.cpp: candidate_growth)
};

/// A face as the host builds it: vertex ids (2g: caster vertex g, 2g+1: its extrusion from the
/// light to infinity), unsigned weight and, for caps and quads, their plane.
struct FaceIn {
  uint ids[4];
  int n;
  int weight;
  int has_plane;
  dvec3 plane_n;
  double plane_k;
};
layout(buffer_reference, scalar) buffer FacesIn { FaceIn f[]; };

layout(push_constant) uniform Push {
  Vec4s positions;  // welded caster vertices (xyz)
  View view;
  FacesIn faces;
  VolumeFaces out_faces;
  uint n;
} pc;

dvec3 position(uint id) { return dvec3(pc.positions.v[id >> 1].xyz); }

/// VolumeBuilder::dir: from the camera to a finite vertex, from the light for an extruded one.
precise dvec3 dir(View view, uint id) {
  return (id & 1u) != 0u ? position(id) - view.light : position(id) - view.clip.eye;
}

bool owns(dvec3 n) {
  return n.x > 0.0 || (n.x == 0.0 && (n.y > 0.0 || (n.y == 0.0 && n.z > 0.0)));
}

void main() {
  const uint t = global_id();
  if (t >= pc.n) return;
  View view = pc.view;
  const ClipView cv = view.clip;
  const FaceIn fin = pc.faces.f[t];
  pc.out_faces.f[t].n = 0;
  dvec4 poly[kMaxClipVertices];
  for (int i = 0; i < fin.n; ++i) {
    const uint id = fin.ids[i];
    poly[i] = (id & 1u) != 0u ? dvec4(position(id) - view.light, 0.0) : dvec4(position(id), 1.0);
    poly[i] = to_clip(cv, poly[i]);
  }
  const int m = clip_polygon(poly, fin.n, view.near, view.guard);
  if (m < 3) return;
  dvec2 s[kMaxClipVertices];
  int count = m;
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (int i = 0; i < m; ++i) {
    if (!(poly[i].w > 0.0)) {
      // project_polygon's fallback for a zero direction: the whole guard-banded screen.
      const double gx = view.guard * cv.width, gy = view.guard * cv.height;
      s[0] = dvec2(-gx, -gy), s[1] = dvec2(gx + cv.width, -gy);
      s[2] = dvec2(gx + cv.width, gy + cv.height), s[3] = dvec2(-gx, gy + cv.height);
      count = 4;
      xmin = -gx, ymin = -gy, xmax = gx + cv.width, ymax = gy + cv.height;
      break;
    }
    s[i] = to_screen(cv, poly[i]).xy;
    xmin = min(xmin, s[i].x), xmax = max(xmax, s[i].x);
    ymin = min(ymin, s[i].y), ymax = max(ymax, s[i].y);
  }
  const double margin = view.margin;
  if (xmax < -margin || ymax < -margin || xmin > cv.width + margin || ymin > cv.height + margin)
    return;
  precise const double det =
      dot3(cross3(dir(view, fin.ids[0]), dir(view, fin.ids[1])), dir(view, fin.ids[2]));
  if (!(det != 0.0)) return;
  if (fin.has_plane != 0 && !(fin.plane_k != 0.0)) return;  // camera in the face's plane
  const double sgn = det > 0.0 ? 1.0 : -1.0;
  VolumeFace f;
  f.own = 0;
  for (int i = 0; i < fin.n; ++i) {
    const uint a = fin.ids[i], b = fin.ids[(i + 1) % fin.n];
    const uint lo = min(a, b), hi = max(a, b);
    const dvec3 nrm = cross3(dir(view, lo), dir(view, hi));
    f.edge[i] = sgn * (a == lo ? nrm : -nrm);
    if (owns(f.edge[i])) f.own |= 1 << i;
  }
  for (int i = fin.n; i < 4; ++i) f.edge[i] = dvec3(0.0);
  f.weight = int(sgn) * fin.weight;
  f.has_plane = fin.has_plane;
  f.plane_n = fin.plane_n;
  f.plane_k = fin.plane_k;
  // The candidate rectangle: the polygon's extent along its longest edge and across it, grown so
  // that it holds every pixel centre whose shadow origin can project inside the polygon.
  int longest = 0;
  double best = -1.0;
  for (int i = 0; i < count; ++i) {
    const dvec2 e = s[(i + 1) % count] - s[i];
    if (dot(e, e) > best) best = dot(e, e), longest = i;
  }
  const dvec2 u = best > 0.0 ? normalize(s[(longest + 1) % count] - s[longest]) : dvec2(1.0, 0.0);
  const dvec2 v = dvec2(-u.y, u.x);
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  for (int i = 0; i < count; ++i) {
    u0 = min(u0, dot(s[i], u)), u1 = max(u1, dot(s[i], u));
    v0 = min(v0, dot(s[i], v)), v1 = max(v1, dot(s[i], v));
  }
  const double grow = view.grow;
  u0 -= grow, u1 += grow, v0 -= grow, v1 += grow;
  f.rect[0] = vec2(u0 * u + v0 * v);
  f.rect[1] = vec2(u1 * u + v0 * v);
  f.rect[2] = vec2(u0 * u + v1 * v);
  f.rect[3] = vec2(u1 * u + v1 * v);
  f.n = fin.n;
  pc.out_faces.f[t] = f;
}
