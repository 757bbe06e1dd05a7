// GEARS on the GPU, shared declarations: the grid camera C [Wang 2014 §3.1] (filled on the host
// from gears::GridCamera) and its projection, exactly GridCamera::project_cells.

layout(buffer_reference, scalar) buffer GridCamera {
  vec3 eye;
  float plane_z;
  vec2 grid_lo;
  vec2 cell_scale;
  int res_x;
  int res_y;
  float far_z;
  float light_max_z;
  float light_min_z;
  int corner_count;
  float side;  // +1 / −1: which side of the light plane this pass computes (z flipped for −1)
  float pad;
  vec4 corners[8];  // light-space light corners used for the extrusion
};

/// Grid-plane coordinates in cell units (not clamped).
vec2 project_cells(GridCamera cam, vec3 q) {
  precise float s = (cam.plane_z - cam.eye.z) / (q.z - cam.eye.z);
  precise float gx = (cam.eye.x + (q.x - cam.eye.x) * s - cam.grid_lo.x) * cam.cell_scale.x;
  precise float gy = (cam.eye.y + (q.y - cam.eye.y) * s - cam.grid_lo.y) * cam.cell_scale.y;
  return vec2(gx, gy);
}

/// Can a triangle whose nearest vertex is at depth zmin block a sample of cell c? Not when every
/// sample of the cell is nearer than the triangle (and the triangle is beyond the light): a segment
/// from a sample to the light stays nearer than both [Wang 2014 §3.1, the cell-depth cull].
bool cell_may_be_blocked(Uints cell_max_z, uint c, float zmin, bool beyond_light) {
  const uint m = cell_max_z.v[c];
  return m != 0u && (!beyond_light || uintBitsToFloat(m - 1u) >= zmin);
}
