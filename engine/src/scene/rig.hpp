// Internal: what posing a model reads (facet/animation.hpp), built by the glTF reader
// (content/gltf_animation.cpp) and shared, immutable, by every copy of the Model.
//
// The node tree is every node of the file in an order where parents come before children; each
// node's rest transform is its TRS (or its matrix, which animations may not target). A pose
// samples the chosen animation's channels into the nodes' TRS and morph weights, composes the
// world matrices down the tree and writes the scene: the model matrices of the objects placed by
// nodes, the file's camera and lights, and the vertices of every deformed mesh (morph targets
// first, then the skin, which puts vertices in world space: their object's matrix is the
// identity, as glTF ignores a skinned mesh node's own transform).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "facet/animation.hpp"
#include "scene/animation.hpp"

namespace facet {

struct Rig {
  struct Node {
    int parent = -1;
    bool matrix = false;  // the file gives a matrix: `rest` holds it and no channel targets the node
    Eigen::Matrix4d rest = Eigen::Matrix4d::Identity();
    Eigen::Vector3d translation = Eigen::Vector3d::Zero(), scale = Eigen::Vector3d::Ones();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
    std::vector<float> weights;  // morph weights (the node's, else its mesh's)
  };
  enum class Path : unsigned char { translation, rotation, scale, weights };
  struct Channel {
    std::uint32_t node = 0;
    Path path = Path::translation;
    std::uint32_t track = 0;  // into Clip::tracks (channels may share a sampler)
  };
  struct Clip {
    std::vector<animation::Track> tracks;
    std::vector<Channel> channels;
  };
  struct Skin {
    std::vector<std::uint32_t> joints;
    std::vector<Eigen::Matrix4d> inverse_bind;
  };
  // A mesh drawn deformed: its rest vertices (structure of arrays, `rest[0..2]` positions,
  // `rest[3..5]` normals, `rest[6..8]` tangents' xyz; absent kinds empty), the targets' deltas
  // (same layout) and the skin's joints and weights (influences x count, by influence; a mesh
  // that is only morphed: one influence, joint 0, the identity).
  struct Deform {
    std::uint32_t mesh = 0;    // Scene::meshes, rewritten by each pose
    std::uint32_t object = 0;  // Scene::objects drawing it
    std::uint32_t node = 0;
    int skin = -1;
    std::size_t count = 0;
    std::vector<float> rest[9];
    std::vector<std::vector<float>> targets;  // per target: 9 streams of `count` (empty streams: none)
    std::vector<std::uint8_t> target_kinds;   // per target: bit 0 positions, 1 normals, 2 tangents
    int influences = 0;
    std::vector<std::uint16_t> joints;
    std::vector<float> weights;
  };
  // An object placed by a node: its model matrix is world(node) x local.
  struct Placed {
    std::uint32_t object = 0;
    std::uint32_t node = 0;
    Eigen::Matrix4d local = Eigen::Matrix4d::Identity();
  };
  struct NodeLight {
    std::uint32_t light = 0;
    std::uint32_t node = 0;
  };

  std::vector<Node> nodes;
  std::vector<std::uint32_t> order;  // parents before children
  std::vector<Clip> clips;           // as MotionInfo::animations
  std::vector<Skin> skins;
  std::vector<Deform> deforms;
  std::vector<Placed> placed;
  std::vector<NodeLight> lights;
  int camera_node = -1;  // the file's camera, when the scene uses it
};

// The world matrix of every node at `seconds` into clip `clip` (-1: the rest pose), and the
// nodes' morph weights.
void pose_nodes(const Rig& rig, int clip, double seconds, std::vector<Eigen::Matrix4d>& world,
                std::vector<std::vector<float>>& weights);

}  // namespace facet
