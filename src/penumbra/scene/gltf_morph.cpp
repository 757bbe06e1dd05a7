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

/// The keys around `ticks` (count > 0): lo == hi holds that key (before the first, after the
/// last), else the fraction s of the way from key lo to key hi.
struct Bracket {
  unsigned lo = 0, hi = 0;
  double s = 0.0;
};
template <class Key>
Bracket bracket(const Key* keys, unsigned count, double ticks) {
  unsigned hi = 0;
  while (hi < count && keys[hi].mTime < ticks) ++hi;
  if (hi == 0) return {0, 0, 0.0};
  if (hi == count) return {count - 1, count - 1, 0.0};
  const double t0 = keys[hi - 1].mTime, t1 = keys[hi].mTime;
  return {hi - 1, hi, t1 > t0 ? (ticks - t0) / (t1 - t0) : 1.0};
}

/// target index → weight at `ticks`, interpolated linearly between the channel's keys.
std::map<unsigned, double> weights_at(const aiMeshMorphAnim& channel, double ticks) {
  const auto key_weights = [&](unsigned k) {
    std::map<unsigned, double> w;
    const aiMeshMorphKey& key = channel.mKeys[k];
    for (unsigned i = 0; i < key.mNumValuesAndWeights; ++i) w[key.mValues[i]] = key.mWeights[i];
    return w;
  };
  const Bracket k = bracket(channel.mKeys, channel.mNumKeys, ticks);
  if (k.lo == k.hi) return key_weights(k.lo);
  std::map<unsigned, double> a = key_weights(k.lo), b = key_weights(k.hi);
  for (const auto& [target, w] : b) a[target] += k.s * (w - a[target]);
  for (auto& [target, w] : a)
    if (!b.count(target)) w *= 1.0 - k.s;
  return a;
}

/// The channels of one animation: morph weights by node name, node transforms by node name.
struct Channels {
  std::map<std::string, const aiMeshMorphAnim*> morph;
  std::map<std::string, const aiNodeAnim*> nodes;
};

/// A channel's value at `ticks`: `rest` without keys, else `mix` of the keys around it (held
/// before the first and after the last).
template <class Key, class Value, class Mix>
Value key_at(const Key* keys, unsigned count, double ticks, Value rest, Mix mix) {
  if (count == 0) return rest;
  const Bracket k = bracket(keys, count, ticks);
  if (k.lo == k.hi) return keys[k.lo].mValue;
  return mix(keys[k.lo].mValue, keys[k.hi].mValue, static_cast<float>(k.s));
}

aiVector3D vector_at(const aiVectorKey* keys, unsigned count, double ticks, aiVector3D rest) {
  return key_at(keys, count, ticks, rest,
                [](const aiVector3D& a, const aiVector3D& b, float s) { return a + s * (b - a); });
}

aiQuaternion rotation_at(const aiQuatKey* keys, unsigned count, double ticks, aiQuaternion rest) {
  return key_at(keys, count, ticks, rest,
                [](const aiQuaternion& a, const aiQuaternion& b, float s) {
                  aiQuaternion out;
                  aiQuaternion::Interpolate(out, a, b, s);  // slerp
                  return out.Normalize();
                });
}

/// Every node's global transform at `ticks`, its animated channel replacing its own transform.
void node_globals(const aiNode* node, const aiMatrix4x4& parent, const Channels& channels,
                  double ticks, std::map<const aiNode*, aiMatrix4x4>& out, int depth) {
  if (!node || depth > kMaxGltfNodeDepth) return;
  aiMatrix4x4 local = node->mTransformation;
  if (const auto it = channels.nodes.find(node->mName.C_Str()); it != channels.nodes.end()) {
    const aiNodeAnim& ch = *it->second;
    aiVector3D scale, position;
    aiQuaternion rotation;
    local.Decompose(scale, rotation, position);
    local = aiMatrix4x4(vector_at(ch.mScalingKeys, ch.mNumScalingKeys, ticks, scale),
                        rotation_at(ch.mRotationKeys, ch.mNumRotationKeys, ticks, rotation),
                        vector_at(ch.mPositionKeys, ch.mNumPositionKeys, ticks, position));
  }
  out[node] = parent * local;
  for (unsigned i = 0; i < node->mNumChildren; ++i)
    node_globals(node->mChildren[i], out[node], channels, ticks, out, depth + 1);
}

const aiNode* find_node(const std::map<const aiNode*, aiMatrix4x4>& globals, const aiString& name) {
  for (const auto& [node, m] : globals)
    if (node->mName == name) return node;
  return nullptr;
}

/// The mesh's vertices after its morph targets (weights of its node's channel).
std::vector<aiVector3D> morphed(const Instance& inst, const Channels& channels, double ticks) {
  const aiMesh& m = *inst.mesh;
  std::vector<aiVector3D> out(m.mVertices, m.mVertices + m.mNumVertices);
  const auto it = channels.morph.find(inst.node->mName.C_Str());
  if (it == channels.morph.end()) return out;
  for (const auto& [target, w] : weights_at(*it->second, ticks)) {
    if (target >= m.mNumAnimMeshes) continue;
    const aiAnimMesh* am = m.mAnimMeshes[target];
    if (!am || !am->mVertices || am->mNumVertices != m.mNumVertices) continue;
    // Assimp stores a glTF target's positions absolute (base + displacement).
    for (unsigned v = 0; v < m.mNumVertices; ++v)
      out[v] += static_cast<float>(w) * (am->mVertices[v] - m.mVertices[v]);
  }
  return out;
}

/// Linear blend skinning: Σ weight · (joint's global · inverse bind) · p, in world space (glTF
/// ignores the skinned mesh's own node transform); unweighted vertices follow the mesh's node.
std::vector<aiVector3D> skinned(const Instance& inst, const std::vector<aiVector3D>& p,
                                const std::map<const aiNode*, aiMatrix4x4>& globals) {
  const aiMesh& m = *inst.mesh;
  std::vector<aiVector3D> sum(p.size(), aiVector3D(0.0f));
  std::vector<float> total(p.size(), 0.0f);
  for (unsigned b = 0; b < m.mNumBones; ++b) {
    const aiBone* bone = m.mBones[b];
    const aiNode* joint = bone ? find_node(globals, bone->mName) : nullptr;
    if (!joint) continue;
    const aiMatrix4x4 skin = globals.at(joint) * bone->mOffsetMatrix;
    for (unsigned w = 0; w < bone->mNumWeights; ++w) {
      const aiVertexWeight& vw = bone->mWeights[w];
      if (vw.mVertexId >= p.size() || !(vw.mWeight > 0.0f)) continue;
      sum[vw.mVertexId] += vw.mWeight * (skin * p[vw.mVertexId]);
      total[vw.mVertexId] += vw.mWeight;
    }
  }
  const aiMatrix4x4& own = globals.at(inst.node);
  for (size_t v = 0; v < p.size(); ++v) sum[v] = total[v] > 0.0f ? sum[v] / total[v] : own * p[v];
  return sum;
}

std::vector<Vec3> positions_at(const aiScene& scene, const std::vector<Instance>& instances,
                               const Channels& channels, double ticks) {
  std::map<const aiNode*, aiMatrix4x4> globals;
  node_globals(scene.mRootNode, aiMatrix4x4(), channels, ticks, globals, 0);
  std::vector<Vec3> out;
  for (const Instance& inst : instances) {
    std::vector<aiVector3D> p = morphed(inst, channels, ticks);
    if (inst.mesh->mNumBones > 0) {
      p = skinned(inst, p, globals);
    } else {
      for (aiVector3D& q : p) q = globals.at(inst.node) * q;
    }
    for (const aiVector3D& q : p) out.emplace_back(q.x, q.y, q.z);
  }
  return out;
}

MorphClip read_clip(const aiScene& scene, const aiAnimation& anim, unsigned index,
                    const std::vector<Instance>& instances) {
  MorphClip clip;
  clip.name = anim.mName.length > 0 ? anim.mName.C_Str() : "animation" + std::to_string(index);
  // glTF's times are seconds; assimp gives them in ticks (1000 per second).
  const double ticks_per_s = anim.mTicksPerSecond > 0.0 ? anim.mTicksPerSecond : 1000.0;
  Channels channels;
  std::vector<double> ticks;
  for (unsigned c = 0; c < anim.mNumMorphMeshChannels; ++c) {
    const aiMeshMorphAnim* ch = anim.mMorphMeshChannels[c];
    if (!ch || ch->mNumKeys == 0) continue;
    channels.morph[ch->mName.C_Str()] = ch;
    for (unsigned k = 0; k < ch->mNumKeys; ++k) ticks.push_back(ch->mKeys[k].mTime);
  }
  for (unsigned c = 0; c < anim.mNumChannels; ++c) {
    const aiNodeAnim* ch = anim.mChannels[c];
    if (!ch) continue;
    channels.nodes[ch->mNodeName.C_Str()] = ch;
    for (unsigned k = 0; k < ch->mNumPositionKeys; ++k) ticks.push_back(ch->mPositionKeys[k].mTime);
    for (unsigned k = 0; k < ch->mNumRotationKeys; ++k) ticks.push_back(ch->mRotationKeys[k].mTime);
    for (unsigned k = 0; k < ch->mNumScalingKeys; ++k) ticks.push_back(ch->mScalingKeys[k].mTime);
  }
  std::sort(ticks.begin(), ticks.end());
  ticks.erase(std::unique(ticks.begin(), ticks.end()), ticks.end());
  for (double t : ticks) {
    clip.times_s.push_back(t / ticks_per_s);
    clip.positions.push_back(positions_at(scene, instances, channels, t));
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
    if (!anim || (anim->mNumMorphMeshChannels == 0 && anim->mNumChannels == 0)) continue;
    clips.push_back(read_clip(*scene, *anim, a, instances));
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
