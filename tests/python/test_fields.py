"""Every material and light field by name (facet.fields, Scene.material / set_material, Scene.light /
set_light): the same table validation, scene files, C and `facet check --fields` read."""
import math

import numpy as np
import pytest

import facet


def other_value(field):
    """A value of the field other than its default, inside its range."""
    d = field["default"]
    t = field["type"]
    if t == "boolean":
        return not d
    if t == "choice":
        return field["choices"][-1] if d == field["choices"][0] else field["choices"][0]
    if t == "colour":
        return (0.25, 0.5, 0.75)
    if t == "vector":
        return tuple(0.5 * (c + 1) if d[c] != 0.5 * (c + 1) else -2.0 for c in range(field["components"]))
    if t in ("number", "integer"):
        lo, hi = [float(x) for x in field["range"].split(" or ")[0].strip("[]").split(", ")]
        mid = lo + 3 if hi > 1e6 else math.floor((lo + hi) / 2)
        value = mid + 1 if mid == d else mid
        return int(value) if t == "integer" else value
    raise AssertionError(t)


def test_texture_fields_take_a_texture_index():
    s = facet.Scene()
    t = s.add_texture(np.zeros((4, 4, 4), dtype=np.uint8))
    m = s.add_material()  # used by no object: no mesh needs uvs
    for f in facet.fields("material"):
        if f["type"] == "texture" and f["components"] == 1:
            s.set_material(m, {f["name"]: t})
            assert s.material(m)[f["name"]] == t
    s.set_material(m, {"environment.mode": "cube", "environment.maps": (t,) * 6})
    assert s.material(m)["environment.maps"] == (t,) * 6


def test_every_material_field_round_trips():
    s = facet.Scene()
    for f in facet.fields("material"):
        if f["type"] == "texture" or f["name"].startswith("environment."):
            continue  # textures need a texture; the environment's fields have rules between them (below)
        v = other_value(f)
        s.set_material(1, {f["name"]: v})
        got = s.material(1)[f["name"]]
        if isinstance(v, tuple):
            assert got == pytest.approx(v), f["name"]
        else:
            assert got == pytest.approx(v) if isinstance(v, float) else got == v, f["name"]


def test_every_light_field_round_trips_on_a_spot_light():
    s = facet.Scene()
    s.set_light(0, {"type": "spot"})
    for f in facet.fields("light"):
        if f["type"] == "texture" or f["name"] in ("type", "attenuation.min", "attenuation.max", "attenuation.model"):
            continue
        v = other_value(f)
        s.set_light(0, {f["name"]: v})
        got = s.light(0)[f["name"]]
        assert got == (pytest.approx(v) if isinstance(v, (float, tuple)) else v), f["name"]
    s.set_light(0, {"attenuation.model": "linear_range", "attenuation.max": 10, "attenuation.min": 2})
    assert s.light(0)["attenuation.max"] == 10


def test_a_refused_set_changes_nothing_and_names_the_field():
    s = facet.Scene()
    before = s.material(0)
    for fields, field in [({"diffuse": (1, 0, 0), "alpha": 2}, "materials[0].alpha"),
                          ({"blend": "sideways"}, "materials[0].blend"),
                          ({"environment.mode": "cube"}, "materials[0].environment.maps[0]"),
                          ({"diffuse_texture": 7}, "materials[0].diffuse_texture"),
                          ({"shininess": "high"}, "materials[0].shininess"),
                          ({"no_such\x1b[2J": 1}, "materials[0]")]:
        with pytest.raises(facet.Error) as e:
            s.set_material(0, fields)
        assert e.value.field == field, str(e.value)
        assert "\x1b" not in str(e.value)
        assert s.material(0) == before
    with pytest.raises(facet.Error) as e:
        s.set_light(0, {"range": 5})  # a directional light has no range
    assert e.value.field == "lights[0].range"


def test_fields_describe_the_table():
    names = [f["name"] for f in facet.fields("material")]
    assert len(names) == len(set(names)) and "environment.strength" in names
    spot = {f["name"]: f for f in facet.fields("light")}["spot.cutoff_deg"]
    assert spot["range"] == "[0, 90] or 180" and spot["default"] == 45
    with pytest.raises(facet.Error):
        facet.fields("camera")
