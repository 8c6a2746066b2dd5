// Python's access to every material and light field by name (the field table, facet/fields.hpp):
// Scene.material(i) / set_material(i, fields) / light(i) / set_light(i, fields) and facet.fields().
// Values as Python gives them: a colour or vector a sequence of numbers, a choice its name, a
// boolean True or False, a texture its index (or -1), an integer an int.
#include <pybind11/stl.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "py_scene.hpp"

namespace facet_py {
namespace {

// The caller's text, short and without control characters, for a message.
std::string shown(const std::string& text) {
  std::string s;
  for (const char c : text.substr(0, 40)) s += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
  return s;
}

// A float field's value as the shortest decimal that reads back as the same float (0.18, not
// 0.18000000715255737).
double shortest(double v) {
  if (!std::isfinite(v)) return v;
  char buf[32];
  for (int digits = 6; digits < 9; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    const double x = std::strtod(buf, nullptr);
    if (static_cast<float>(x) == static_cast<float>(v)) return x;
  }
  return v;
}

template <class T>
py::object to_python(const FieldSpec<T>& f, const T& object) {
  auto one = [&](int c) -> py::object {
    const double v = f.get(object, c);
    switch (f.type) {
      case FieldType::boolean: return py::bool_(v != 0.0);
      case FieldType::choice: {
        const auto i = static_cast<std::size_t>(v);
        return i < f.choices.size() ? py::object(py::str(f.choices[i])) : py::object(py::int_(static_cast<long>(v)));
      }
      case FieldType::integer:
      case FieldType::texture: return py::int_(static_cast<long long>(v));
      default: return py::float_(shortest(v));
    }
  };
  if (f.components == 1) return one(0);
  py::list l;
  for (int c = 0; c < f.components; ++c) l.append(one(c));
  return py::tuple(l);
}

// One Python value as the field's number: a choice by name, a bool as 0 or 1, a number as itself
// (a non-number is an error naming the field).
template <class T>
double number_of(const FieldSpec<T>& f, const py::handle& v, const std::string& path) {
  if (f.type == FieldType::choice) {
    if (!py::isinstance<py::str>(v)) raise({ErrorCode::invalid_argument, path, path + ": expected the name of one of " + describe_range(f)});
    const std::string name = v.cast<std::string>();
    for (std::size_t i = 0; i < f.choices.size(); ++i)
      if (name == f.choices[i]) return double(i);
    raise({ErrorCode::invalid_argument, path, path + ": unknown value '" + shown(name) + "' (expected one of " + describe_range(f) + ")"});
  }
  if (f.type == FieldType::boolean) {
    if (!py::isinstance<py::bool_>(v)) raise({ErrorCode::invalid_argument, path, path + ": expected True or False"});
    return v.cast<bool>() ? 1.0 : 0.0;
  }
  if (py::isinstance<py::bool_>(v) || !(py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v))) {
    raise({ErrorCode::invalid_argument, path, path + ": expected a number"});
  }
  if (py::isinstance<py::int_>(v)) {
    // Beyond what a double holds exactly (and far beyond any range): refused, not rounded.
    const py::int_ big(1LL << 53);
    if (v.attr("__abs__")().cast<py::int_>().attr("__gt__")(big).cast<bool>()) {
      raise({ErrorCode::invalid_argument, path, path + ": expected a number in " + describe_range(f)});
    }
    return double(v.cast<long long>());
  }
  return v.cast<double>();
}

template <class T>
std::vector<double> values_of(const FieldSpec<T>& f, const py::handle& v, const std::string& path) {
  std::vector<double> out;
  if (f.components == 1) {
    out.push_back(number_of(f, v, path));
    return out;
  }
  // A two-component vector may be one number for both (uv_scale), as in a scene file.
  if (f.components == 2 && f.type == FieldType::vector && (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v))) {
    const double x = number_of(f, v, path);
    return {x, x};
  }
  if (py::isinstance<py::str>(v) || !py::isinstance<py::sequence>(v) || py::len(v) != std::size_t(f.components)) {
    raise({ErrorCode::invalid_argument, path, path + ": expected " + std::to_string(f.components) + " values (" + describe_range(f) + ")"});
  }
  for (const py::handle item : v.template cast<py::sequence>()) out.push_back(number_of(f, item, path));
  return out;
}

template <class T, class Find>
void set_fields(T& object, const py::dict& fields, const std::string& prefix, Find find) {
  for (const auto& [key, value] : fields) {
    if (!py::isinstance<py::str>(key)) raise({ErrorCode::invalid_argument, prefix, prefix + ": field names are strings"});
    const std::string name = key.template cast<std::string>();
    const FieldSpec<T>* f = find(name);
    if (!f) raise({ErrorCode::invalid_argument, prefix, prefix + ": no field named '" + shown(name) + "' (facet.fields() lists them)"});
    const std::string path = prefix + "." + name;
    const std::vector<double> v = values_of(*f, value, path);
    if (Status st = set_field(*f, object, v, path); !st.ok()) raise(st);
  }
}

template <class T>
py::dict all_fields(std::span<const FieldSpec<T>> table, const T& object) {
  py::dict d;
  for (const FieldSpec<T>& f : table) d[f.name] = to_python(f, object);
  return d;
}

template <class T>
py::list describe_table(std::span<const FieldSpec<T>> table) {
  py::list l;
  const T fresh{};
  for (const FieldSpec<T>& f : table) {
    py::dict d;
    d["name"] = f.name;
    d["type"] = to_string(f.type);
    d["components"] = f.components;
    d["range"] = describe_range(f);
    d["default"] = to_python(f, fresh);
    d["doc"] = f.doc;
    py::list choices;
    for (const char* c : f.choices) choices.append(c);
    d["choices"] = choices;
    l.append(d);
  }
  return l;
}

}  // namespace

void bind_fields(py::module_& m, py::class_<PyScene>& scene_class) {
  m.def("fields", [](const std::string& kind) {
    if (kind == "material") return describe_table(material_fields());
    if (kind == "light") return describe_table(light_fields());
    raise({ErrorCode::invalid_argument, "kind", "kind: expected 'material' or 'light', found '" + shown(kind) + "'"});
  }, py::arg("kind") = "material",
        "The fields of a material or a light: a list of dicts (name, type, components, range, default, doc, choices), "
        "the same names as the scene file's and Scene.set_material's.");
  scene_class
      .def("material", [](const PyScene& ps, std::size_t index) {
        if (index >= ps.scene.materials.size()) raise({ErrorCode::invalid_argument, "index", "index: no material " + std::to_string(index)});
        return all_fields(material_fields(), ps.scene.materials[index]);
      }, py::arg("index"), "Every field of material `index` as a dict (facet.fields('material') describes them).")
      .def("set_material", [](PyScene& ps, std::size_t index, const py::dict& fields) {
        Scene& s = ps.edit();
        if (index >= s.materials.size()) raise({ErrorCode::invalid_argument, "index", "index: no material " + std::to_string(index)});
        const std::string prefix = "materials[" + std::to_string(index) + "]";
        Material mat = s.materials[index];
        set_fields(mat, fields, prefix, [](const std::string& n) { return find_material_field(n); });
        // The material alone, then the scene with it (textures exist, meshes have uvs): a failure changes nothing.
        if (Status st = replace_material(s, index, mat); !st.ok()) raise(st);
      }, py::arg("index"), py::arg("fields"),
         "Changes the named fields of material `index`, e.g. {'diffuse': (1, 0, 0), 'blend': 'alpha', "
         "'environment.strength': 0.5}; checked as a whole, nothing changes on an error.")
      .def("light", [](const PyScene& ps, std::size_t index) {
        if (index >= ps.scene.lights.size()) raise({ErrorCode::invalid_argument, "index", "index: no light " + std::to_string(index)});
        return all_fields(light_fields(), ps.scene.lights[index]);
      }, py::arg("index"), "Every field of light `index` as a dict (facet.fields('light') describes them).")
      .def("set_light", [](PyScene& ps, std::size_t index, const py::dict& fields) {
        Scene& s = ps.edit();
        if (index >= s.lights.size()) raise({ErrorCode::invalid_argument, "index", "index: no light " + std::to_string(index)});
        const std::string prefix = "lights[" + std::to_string(index) + "]";
        Light l = s.lights[index];
        set_fields(l, fields, prefix, [](const std::string& n) { return find_light_field(n); });
        if (Status st = replace_light(s, index, l); !st.ok()) raise(st);  // (the scene's limits: shadowed lights, projectors)
      }, py::arg("index"), py::arg("fields"),
         "Changes the named fields of light `index`, e.g. {'diffuse': (2, 2, 2), 'shadow.method': 'map', "
         "'shadow.bias.normal': 2}; checked as a whole, nothing changes on an error.");
}

}  // namespace facet_py
