// Internal: glTF 2.0 into a facet Scene. The Document (gltf_document.hpp) has checked the
// container, the buffers and the bufferViews; the reader walks the default scene's node trees and
// reads the meshes, materials, textures, cameras and lights they use, checking every field it
// reads (type, range, index) and naming its JSON path. docs/content.md documents the mapping.
// gltf.cpp: nodes, accessors and meshes; gltf_material.cpp: materials, textures, cameras, lights.
#pragma once

#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "content/gltf_document.hpp"
#include "facet/model.hpp"
#include "scene/rig.hpp"

namespace facet::gltf {

constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123, kUnsignedInt = 5125,
              kFloat = 5126;

// KHR_texture_transform as the affine map it is on glTF's texture coordinates:
// uv' = [a b c; d e f] (u, v, 1).
struct UvTransform {
  double m[6] = {1, 0, 0, 0, 1, 0};
  bool identity() const { return m[0] == 1 && m[1] == 0 && m[2] == 0 && m[3] == 0 && m[4] == 1 && m[5] == 0; }
  bool operator==(const UvTransform& o) const {
    for (int i = 0; i < 6; ++i)
      if (m[i] != o.m[i]) return false;
    return true;
  }
};

class Reader {
 public:
  Reader(const Document& doc, const io::AssetFolder& folder, const ModelOptions& options, Model& out)
      : doc_(doc), f_(doc.fields()), folder_(folder), options_(options), out_(out) {}

  Status read(std::uint64_t bytes_used);

 private:
  struct MaterialInfo {
    std::uint32_t index = 0;
    Color3 vertex_color_scale{1.0f, 1.0f, 1.0f};
    bool double_sided = false;
    bool needs_uvs = false;
    bool uses_alpha = false;  // alphaMode MASK or BLEND
    bool normal_map = false;  // needs tangents: TANGENT, or generated
    UvTransform uv_transform;
  };
  // One attribute's values, count x components doubles.
  struct Values {
    std::vector<double> v;
    int components = 0;
    std::size_t count() const { return components ? v.size() / std::size_t(components) : 0; }
  };
  static constexpr std::uint32_t kSkipped = ~std::uint32_t{0};

  void warn(const std::string& what) { out_.warnings.push_back(what); }
  Status reserve(std::uint64_t bytes, const std::string& p);

  // gltf.cpp
  Status check_extensions();
  Status walk(std::size_t scene_index);
  Status local_matrix(const Json& node, const std::string& p, Eigen::Matrix4d& out) const;
  Status read_accessor(int index, const std::string& p, const char* semantic, Values& out);
  Status view_span(int view, std::uint64_t offset, std::uint64_t count, std::size_t element_bytes,
                   std::size_t stride, const std::string& p, const std::uint8_t*& data) const;
  Status add_mesh_instances(int mesh, const std::string& node_path, const Eigen::Matrix4d& world);
  Status add_gpu_instances(int mesh, const std::string& node_path, const Eigen::Matrix4d& world, const Json& extension);
  Status primitive(std::size_t m, std::size_t k, std::uint32_t& mesh_index, std::uint32_t& material_index,
                   bool& double_sided);
  Status draco_attributes(const Json& ext, const std::string& p, const std::map<std::string, int>& attributes,
                          std::map<std::string, Values>& values, std::vector<std::uint32_t>& indices);

  // gltf_animation.cpp: what moves (scene/rig.hpp)
  // Whether meshes[mesh] is drawn deformed by a node with `skin` (-1: none): it has morph targets,
  // or the skin and JOINTS_0/WEIGHTS_0.
  Status deforms(int mesh, int skin, bool& out);
  Status add_deformed(int mesh, int skin, std::size_t node, const std::string& node_path, const Eigen::Matrix4d& world);
  Status place(std::size_t node, std::size_t first_object, const Eigen::Matrix4d& world);
  Status read_skin(int skin, int& rig_skin);
  Status read_targets(std::size_t m, std::size_t k, const std::vector<std::uint32_t>& origin, Rig::Deform& d);
  Status read_skin_weights(std::size_t m, std::size_t k, const std::vector<std::uint32_t>& origin, std::size_t joints,
                           Rig::Deform& d);
  Status rig_nodes();
  Status read_animation(std::size_t a);
  Status finish_rig();

  // gltf_material.cpp
  Status material(int index, MaterialInfo& info);
  // `encoding`: glTF's rule for the slot (base colour and emission sRGB, the others linear),
  // whatever the image file says.
  Status texture_info(const Json& ti, const std::string& tp, std::int32_t& t, UvTransform& transform, bool& has_transform,
                      TextureEncoding encoding);
  Status texture(int index, std::int32_t& out, TextureEncoding encoding);
  Status pbr_extensions(const Json* ext, const std::string& p, Material& mat);
  std::uint32_t untextured_twin(std::uint32_t index);
  Status add_camera(int camera, std::size_t node, const std::string& p, const Eigen::Matrix4d& world);
  Status add_light(const Json& ext, const std::string& p, const Eigen::Matrix4d& world);

  const Document& doc_;
  const Fields& f_;
  const io::AssetFolder& folder_;
  const ModelOptions& options_;
  Model& out_;
  std::uint64_t used_ = 0;
  bool cameras_noted_ = false;
  std::map<std::pair<std::size_t, std::size_t>, std::tuple<std::uint32_t, std::uint32_t, bool>> primitives_;
  std::map<int, MaterialInfo> materials_;
  std::map<std::uint32_t, std::uint32_t> untextured_;
  std::map<std::tuple<int, TextureFilter, TextureWrap, TextureEncoding>, std::int32_t> textures_;
  std::set<std::string> ignored_attributes_;
  // What moves: built while walking, handed to Model::rig when anything does.
  bool animated_ = false;
  std::shared_ptr<Rig> rig_ = std::make_shared<Rig>();
  std::map<std::pair<std::size_t, std::size_t>, std::vector<std::uint32_t>> origins_;
  std::map<int, int> skins_;  // skins[i] -> Rig::skins
  std::vector<Rig::NodeLight> node_lights_;
  int camera_node_ = -1;
};

}  // namespace facet::gltf
