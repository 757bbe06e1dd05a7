#include "penumbra/gpu/shaders.hpp"

namespace penumbra::gpu {

namespace {

// glslc -mfmt=num writes each module as a comma-separated list of words.
const uint32_t kScanBlock[] = {
#include "scan_block.comp.inc"
};
const uint32_t kScanAdd[] = {
#include "scan_add.comp.inc"
};
const uint32_t kRadixHist[] = {
#include "radix_hist.comp.inc"
};
const uint32_t kRadixScatter[] = {
#include "radix_scatter.comp.inc"
};
const uint32_t kRadixScatterCompare[] = {
#include "radix_scatter_compare.comp.inc"
};
const uint32_t kGearsCells[] = {
#include "gears_cells.comp.inc"
};
const uint32_t kGearsCount[] = {
#include "gears_count.comp.inc"
};
const uint32_t kGearsWrite[] = {
#include "gears_write.comp.inc"
};
const uint32_t kGearsRanges[] = {
#include "gears_ranges.comp.inc"
};
const uint32_t kGearsLongest[] = {
#include "gears_longest.comp.inc"
};
const uint32_t kGearsRaster[] = {
#include "gears_raster.comp.inc"
};
const uint32_t kGearsSamples[] = {
#include "gears_samples.comp.inc"
};
const uint32_t kDepthMin[] = {
#include "depth_min.comp.inc"
};
const uint32_t kShadowLookup[] = {
#include "shadow_lookup.comp.inc"
};
const uint32_t kShadowLookupF64[] = {
#include "shadow_lookup_f64.comp.inc"
};
const uint32_t kDepthMapVert[] = {
#include "depth_map.vert.inc"
};
const uint32_t kDepthMapFrag[] = {
#include "depth_map.frag.inc"
};
const uint32_t kDepthMapExactVert[] = {
#include "depth_map_exact.vert.inc"
};
const uint32_t kDepthMapExactFrag[] = {
#include "depth_map_exact.frag.inc"
};
const uint32_t kDepthSetup[] = {
#include "depth_setup.comp.inc"
};
const uint32_t kVolumeSetup[] = {
#include "volume_setup.comp.inc"
};
const uint32_t kVolumeVert[] = {
#include "volume.vert.inc"
};
const uint32_t kVolumeFrag[] = {
#include "volume.frag.inc"
};
const uint32_t kDcsInit[] = {
#include "dcs_init.comp.inc"
};
const uint32_t kDcsEdges[] = {
#include "dcs_edges.comp.inc"
};
const uint32_t kDcsStsv[] = {
#include "dcs_stsv.comp.inc"
};
const uint32_t kDcsFinish[] = {
#include "dcs_finish.comp.inc"
};
const uint32_t kWedgesPass2[] = {
#include "wedges_pass2.comp.inc"
};
const uint32_t kWedgesPass2Textured[] = {
#include "wedges_pass2_textured.comp.inc"
};
const uint32_t kVolumeCount[] = {
#include "volume_count.comp.inc"
};
const uint32_t kDepthRaster[] = {
#include "depth_raster.comp.inc"
};
const uint32_t kWedgeBlendPass2[] = {
#include "wedge_blend_pass2.comp.inc"
};
const uint32_t kWedgeBlendPass2Textured[] = {
#include "wedge_blend_pass2_textured.comp.inc"
};
const uint32_t kSsmBlend[] = {
#include "ssm_blend.comp.inc"
};
const uint32_t kSilmapLayer[] = {
#include "silmap_layer.comp.inc"
};
const uint32_t kSilmapLookup[] = {
#include "silmap_lookup.comp.inc"
};

}  // namespace

std::span<const uint32_t> spirv(Shader shader) {
  switch (shader) {
    case Shader::scan_block:
      return kScanBlock;
    case Shader::scan_add:
      return kScanAdd;
    case Shader::radix_hist:
      return kRadixHist;
    case Shader::radix_scatter:
      return kRadixScatter;
    case Shader::radix_scatter_compare:
      return kRadixScatterCompare;
    case Shader::gears_cells:
      return kGearsCells;
    case Shader::gears_count:
      return kGearsCount;
    case Shader::gears_write:
      return kGearsWrite;
    case Shader::gears_ranges:
      return kGearsRanges;
    case Shader::gears_longest:
      return kGearsLongest;
    case Shader::gears_raster:
      return kGearsRaster;
    case Shader::gears_samples:
      return kGearsSamples;
    case Shader::depth_min:
      return kDepthMin;
    case Shader::shadow_lookup:
      return kShadowLookup;
    case Shader::shadow_lookup_f64:
      return kShadowLookupF64;
    case Shader::depth_map_vert:
      return kDepthMapVert;
    case Shader::depth_map_frag:
      return kDepthMapFrag;
    case Shader::depth_map_exact_vert:
      return kDepthMapExactVert;
    case Shader::depth_map_exact_frag:
      return kDepthMapExactFrag;
    case Shader::depth_setup:
      return kDepthSetup;
    case Shader::volume_setup:
      return kVolumeSetup;
    case Shader::volume_vert:
      return kVolumeVert;
    case Shader::volume_frag:
      return kVolumeFrag;
    case Shader::dcs_init:
      return kDcsInit;
    case Shader::dcs_edges:
      return kDcsEdges;
    case Shader::dcs_stsv:
      return kDcsStsv;
    case Shader::dcs_finish:
      return kDcsFinish;
    case Shader::ssm_blend:
      return kSsmBlend;
    case Shader::wedges_pass2:
      return kWedgesPass2;
    case Shader::wedges_pass2_textured:
      return kWedgesPass2Textured;
    case Shader::volume_count:
      return kVolumeCount;
    case Shader::depth_raster:
      return kDepthRaster;
    case Shader::wedge_blend_pass2:
      return kWedgeBlendPass2;
    case Shader::silmap_layer:
      return kSilmapLayer;
    case Shader::silmap_lookup:
      return kSilmapLookup;
    case Shader::wedge_blend_pass2_textured:
      return kWedgeBlendPass2Textured;
    case Shader::count_:
      break;
  }
  return {};
}

const ComputePipeline& Programs::get(Shader shader) {
  auto& p = pipelines_[static_cast<int>(shader)];
  if (!p) p = std::make_unique<ComputePipeline>(ctx_, spirv(shader));
  return *p;
}

}  // namespace penumbra::gpu
