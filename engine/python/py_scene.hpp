// The Python module's shared parts: facet.Error and the Scene object (facet_module.cpp binds the
// module; fields_module.cpp the field access by name).
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

#include "facet/facet.hpp"

namespace facet_py {

namespace py = pybind11;
using namespace facet;

// facet.Error(message) with .code ("invalid_argument", "parse_error", "io_error", "unsupported",
// "out_of_memory", "cancelled") and .field (the JSON path or option named, may be empty). The
// class lives in the module (looked up there: the binding keeps no state of its own).
[[noreturn]] inline void raise(const Status& s) {
  py::object type = py::module_::import("facet._facet").attr("Error");
  py::object e = type(s.message());
  static constexpr const char* kCodes[] = {"ok", "invalid_argument", "parse_error", "io_error", "unsupported", "out_of_memory", "cancelled"};
  const auto code = static_cast<std::size_t>(s.code());
  e.attr("code") = code < std::size(kCodes) ? kCodes[code] : "unknown";
  e.attr("field") = s.field();
  PyErr_SetObject(type.ptr(), e.ptr());
  throw py::error_already_set();
}

// A Scene as Python holds it.
struct PyScene {
  Scene scene;
  int rendering = 0;
  std::vector<std::string> warnings;  // what loading read approximately or not at all
  std::vector<std::string> cameras;   // a loaded glTF file's cameras (Model::cameras)
  bool model = false;                 // loaded from a model (.gltf, .glb, .obj): Renderer's "auto" shading is Phong
  // A loaded glTF model's motion (facet/animation.hpp): what Scene.pose reads.
  std::shared_ptr<const Rig> rig;
  MotionInfo motion;
  bool file_camera = false;

  Scene& edit() {
    if (rendering > 0) {
      raise({ErrorCode::invalid_argument, "scene",
             "scene: it is being rendered on another thread; change it after that render returns (or render a copy)"});
    }
    return scene;
  }
};

// Binds Scene.animations and Scene.pose (animation_module.cpp).
void bind_animation(py::class_<PyScene>& scene_class);

// Binds Scene.material / set_material / light / set_light and facet.fields (fields_module.cpp).
void bind_fields(py::module_& m, py::class_<PyScene>& scene_class);

}  // namespace facet_py
