// The CPU depth-map rasterizer's screen polygons (raster/projection.cpp, raster/depth_map.cpp) on
// devices with shaderFloat64: depth_setup.comp projects, culls and clips every caster triangle in
// double exactly as project_polygon does; depth_map_exact.vert draws the polygon's pixel box and
// depth_map_exact.frag keeps the texel centres that rasterize_triangle's edge functions and
// top-left rule accept, with its 1/w interpolation. Hardware coverage (vertices snapped to a
// sub-texel grid) then no longer decides which texels a caster edge covers.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require

/// kMaxClipVertices of raster/projection.hpp.
const int kMaxPolyVertices = 9;  // kMaxClipVertices

/// One caster triangle after projection and clipping: `count` screen vertices (x, y, 1/w), 0 when
/// culled; the pixel box the CPU scans, [x0, x1] × [y0, y1] inclusive.
struct ScreenPoly {
  dvec3 v[kMaxPolyVertices];
  int count;
  int x0, y0, x1, y1;
};
layout(buffer_reference, scalar) buffer ScreenPolys { ScreenPoly p[]; };
