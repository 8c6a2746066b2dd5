// Scene.animations and Scene.pose: a loaded glTF model's animations, posed at any time
// (facet/animation.hpp, docs/animation.md).
#include <cmath>

#include <pybind11/stl.h>

#include "py_scene.hpp"

namespace facet_py {

void bind_animation(py::class_<PyScene>& scene_class) {
  scene_class
      .def_property_readonly("animations", [](const PyScene& ps) {
        py::list out;
        for (const AnimationInfo& a : ps.motion.animations) {
          py::dict d;
          d["name"] = a.name;
          d["start_s"] = a.start_s;
          d["end_s"] = a.end_s;
          d["channels"] = a.channels;
          out.append(d);
        }
        return out;
      }, "A loaded glTF model's animations: a list of dicts (name, start_s, end_s, channels); [] for anything else.")
      .def("pose", [](PyScene& ps, const py::object& animation, std::optional<double> time) {
        Scene& s = ps.edit();
        if (!ps.rig) {
          raise({ErrorCode::invalid_argument, "animation", "animation: the scene was not loaded from a model that moves"});
        }
        int index = -1;
        if (py::isinstance<py::str>(animation)) {
          Result<int> found = find_animation(ps.motion, animation.cast<std::string>());
          if (!found) raise(found.status());
          index = *found;
        } else if (!animation.is_none()) {
          index = animation.cast<int>();
        }
        if (time && !std::isfinite(*time)) raise({ErrorCode::invalid_argument, "time", "time: not a finite number"});
        const double seconds = time ? *time : (index >= 0 && std::size_t(index) < ps.motion.animations.size() ? ps.motion.animations[std::size_t(index)].start_s : 0.0);
        PoseOptions po;
        po.animation = index;
        if (const Status st = pose_scene(s, ps.rig.get(), ps.file_camera, seconds, po); !st.ok()) raise(st);
      }, py::arg("animation") = 0, py::arg("time") = py::none(),
        "Poses a loaded glTF model at `time` seconds into `animation` (an index, a name, or None for the rest pose; "
        "time defaults to the animation's first key and clamps to its keys): objects move, skinned and morphed meshes are "
        "rewritten, the file's camera and lights follow their nodes.");
}

}  // namespace facet_py
