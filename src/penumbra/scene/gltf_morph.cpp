#include "penumbra/scene/gltf_morph.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <map>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/gltf_header.hpp"

namespace penumbra {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& reason) {
  throw Error("cannot load mesh " + quote(path.string(), 200) + ": " + reason);
}

struct Instance {
  const aiMesh* mesh;
  const aiNode* node;
  aiMatrix4x4 transform;
};

/// The triangle meshes in load_mesh_file's order (mesh_loader.cpp's collect_instances).
void collect(const aiScene& scene, const aiNode* node, const aiMatrix4x4& parent,
             std::vector<Instance>& out, int depth) {
  if (!node || depth > kMaxGltfNodeDepth) return;
  const aiMatrix4x4 transform = parent * node->mTransformation;
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const unsigned index = node->mMeshes[i];
    const aiMesh* m = index < scene.mNumMeshes ? scene.mMeshes[index] : nullptr;
    if (m && (m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) && m->mNumFaces > 0 && m->mVertices)
      out.push_back({m, node, transform});
  }
  for (unsigned i = 0; i < node->mNumChildren; ++i)
    collect(scene, node->mChildren[i], transform, out, depth + 1);
}

/// target index → weight at `ticks`, interpolated linearly between the channel's keys.
std::map<unsigned, double> weights_at(const aiMeshMorphAnim& channel, double ticks) {
  const auto key_weights = [&](unsigned k) {
    std::map<unsigned, double> w;
    const aiMeshMorphKey& key = channel.mKeys[k];
    for (unsigned i = 0; i < key.mNumValuesAndWeights; ++i) w[key.mValues[i]] = key.mWeights[i];
    return w;
  };
  unsigned hi = 0;
  while (hi < channel.mNumKeys && channel.mKeys[hi].mTime < ticks) ++hi;
  if (hi == 0) return key_weights(0);
  if (hi == channel.mNumKeys) return key_weights(hi - 1);
  const double t0 = channel.mKeys[hi - 1].mTime, t1 = channel.mKeys[hi].mTime;
  const double s = t1 > t0 ? (ticks - t0) / (t1 - t0) : 1.0;
  std::map<unsigned, double> a = key_weights(hi - 1), b = key_weights(hi);
  for (const auto& [target, w] : b) a[target] += s * (w - a[target]);
  for (auto& [target, w] : a)
    if (!b.count(target)) w *= 1.0 - s;
  return a;
}

std::vector<Vec3> positions_at(const std::vector<Instance>& instances,
                               const std::map<std::string, const aiMeshMorphAnim*>& channels,
                               double ticks) {
  std::vector<Vec3> out;
  for (const Instance& inst : instances) {
    const aiMesh& m = *inst.mesh;
    const auto it = channels.find(inst.node->mName.C_Str());
    std::map<unsigned, double> weights;
    if (it != channels.end()) weights = weights_at(*it->second, ticks);
    for (unsigned v = 0; v < m.mNumVertices; ++v) {
      aiVector3D p = m.mVertices[v];
      for (const auto& [target, w] : weights) {
        if (target >= m.mNumAnimMeshes) continue;
        const aiAnimMesh* am = m.mAnimMeshes[target];
        if (!am || !am->mVertices || am->mNumVertices != m.mNumVertices) continue;
        // Assimp stores a glTF target's positions absolute (base + displacement).
        p += static_cast<float>(w) * (am->mVertices[v] - m.mVertices[v]);
      }
      const aiVector3D q = inst.transform * p;
      out.emplace_back(q.x, q.y, q.z);
    }
  }
  return out;
}

MorphClip read_clip(const aiAnimation& anim, unsigned index,
                    const std::vector<Instance>& instances) {
  MorphClip clip;
  clip.name = anim.mName.length > 0 ? anim.mName.C_Str() : "animation" + std::to_string(index);
  // glTF's times are seconds; assimp gives them in ticks (1000 per second).
  const double ticks_per_s = anim.mTicksPerSecond > 0.0 ? anim.mTicksPerSecond : 1000.0;
  std::map<std::string, const aiMeshMorphAnim*> channels;
  std::vector<double> ticks;
  for (unsigned c = 0; c < anim.mNumMorphMeshChannels; ++c) {
    const aiMeshMorphAnim* ch = anim.mMorphMeshChannels[c];
    if (!ch || ch->mNumKeys == 0) continue;
    channels[ch->mName.C_Str()] = ch;
    for (unsigned k = 0; k < ch->mNumKeys; ++k) ticks.push_back(ch->mKeys[k].mTime);
  }
  std::sort(ticks.begin(), ticks.end());
  ticks.erase(std::unique(ticks.begin(), ticks.end()), ticks.end());
  for (double t : ticks) {
    clip.times_s.push_back(t / ticks_per_s);
    clip.positions.push_back(positions_at(instances, channels, t));
  }
  return clip;
}

}  // namespace

std::vector<MorphClip> read_gltf_morph_clips(const std::filesystem::path& path,
                                             size_t rest_vertices) {
  Assimp::Importer importer;
  // load_mesh_file's import, flag for flag: the same vertices in the same order.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_SortByPType | aiProcess_ValidateDataStructure;
  const aiScene* scene = importer.ReadFile(path.string(), flags);
  if (!scene || !scene->mRootNode) fail(path, importer.GetErrorString());
  std::vector<Instance> instances;
  collect(*scene, scene->mRootNode, aiMatrix4x4(), instances, 0);
  std::vector<MorphClip> clips;
  for (unsigned a = 0; a < scene->mNumAnimations; ++a) {
    const aiAnimation* anim = scene->mAnimations[a];
    if (!anim || anim->mNumMorphMeshChannels == 0) continue;
    clips.push_back(read_clip(*anim, a, instances));
    for (const std::vector<Vec3>& p : clips.back().positions) {
      if (p.size() != rest_vertices)
        fail(path, "its animation has " + std::to_string(p.size()) + " vertices, the mesh " +
                       std::to_string(rest_vertices));
      for (const Vec3& v : p)
        if (!is_finite(v)) fail(path, "its animation has NaN or infinite positions");
    }
  }
  return clips;
}

}  // namespace penumbra
