// Deferred shadow-volume counting on the GPU [Forest 2008 §2.2.1, App. 3.A] (shadow_volume_vk.cpp):
// the faces of the summed volume (near caps, far caps and silhouette quads at infinity, built on
// the host as the CPU method builds them) are set up by volume_setup.comp, drawn by the graphics
// pipeline as screen rectangles that contain every candidate pixel, and volume.frag adds the
// face's z-fail weight (+ leaving, − entering, behind the receiver only) where the CPU's exact
// per-pixel test accepts the pixel's shadow origin: additive blending into an R32F target is the
// stencil buffer (counts stay small integers: exact in float).
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require

/// A face ready for the per-pixel test with q = shadow origin − camera (shadow_volume.cpp's Face).
struct VolumeFace {
  dvec3 edge[4];  // q inside the face's cone iff dot(edge[i], q) > 0, or == 0 with own bit i
  dvec3 plane_n;  // the face is behind q iff (dot(plane_n, q) + plane_k) · plane_k > 0
  double plane_k;
  int n;          // 3 or 4; 0: culled (off screen or seen edge-on)
  int own;
  int weight;     // signed: + back-facing from the camera, − front-facing
  int has_plane;  // far caps (at infinity) have none: always behind
  vec2 rect[4];   // screen pixels (y down): a rectangle containing the polygon ⊕ the margin
};
layout(buffer_reference, scalar) buffer VolumeFaces { VolumeFace f[]; };
layout(buffer_reference, scalar) buffer Doubles4 { dvec4 v[]; };

precise double volume_dot3(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// The CPU's per-pixel test of face f (shadow_volume.cpp) for q = shadow origin − camera: inside
/// the face's cone (its edge planes through the camera, with the tie bits), and the face behind
/// the receiver (its plane; far caps always are).
bool volume_test(VolumeFaces faces, uint f, dvec3 q) {
  const int n = faces.f[f].n, own = faces.f[f].own;
  for (int e = 0; e < n; ++e) {
    precise const double d = volume_dot3(faces.f[f].edge[e], q);
    if (d < 0.0 || (d == 0.0 && ((own >> e) & 1) == 0)) return false;
  }
  if (faces.f[f].has_plane != 0) {
    const double k = faces.f[f].plane_k;
    precise const double side = (volume_dot3(faces.f[f].plane_n, q) + k) * k;
    if (!(side > 0.0)) return false;
  }
  return true;
}
