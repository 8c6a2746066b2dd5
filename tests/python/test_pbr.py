"""PBR materials and their surroundings from Python (docs/pbr.md)."""
import numpy as np
import pytest

import facet


def pbr_sphere_scene():
    # The built-in scene's materials made PBR: base colour, metallic and roughness by field name.
    scene = facet.Scene()
    m = 0
    while True:
        try:
            scene.material(m)
        except Exception:
            break
        scene.set_material(m, {"model": "pbr", "base_color": (0.9, 0.6, 0.3), "roughness": 0.4})
        m += 1
    assert m >= 3
    return scene


def test_environment_sources_read_back_and_refuse_bad_input():
    scene = facet.Scene()
    assert scene.environment["source"] == "none"
    scene.set_environment("studio", intensity=2.0, rotation_deg=30.0)
    assert scene.environment == {"source": "studio", "width": 0, "height": 0, "intensity": 2.0, "rotation_deg": 30.0}
    sky = np.full((8, 16, 3), 0.5, dtype=np.float32)
    scene.set_environment(sky)
    assert scene.environment["source"] == "image" and scene.environment["width"] == 16
    for bad in (np.full((8, 15, 3), 0.5, dtype=np.float32), np.full((8, 16, 2), 0.5, dtype=np.float32)):
        with pytest.raises(facet.Error):
            scene.set_environment(bad)
    nan = sky.copy()
    nan[3, 4, 1] = np.nan
    with pytest.raises(facet.Error, match="texel"):
        scene.set_environment(nan)
    with pytest.raises(facet.Error):
        scene.set_environment("studio", intensity=-1.0)
    with pytest.raises(facet.Error):
        scene.set_environment("/no/such/sky.hdr")
    assert scene.environment["source"] == "image"  # unchanged by the refusals


def test_pbr_materials_are_lit_by_the_surroundings():
    scene = pbr_sphere_scene()
    renderer = facet.Renderer(threads=1, shading="phong")
    scene.set_environment("none")
    dark = renderer.render(scene, 64, 36, dtype="float32")
    scene.set_environment("studio", intensity=4.0)
    bright = renderer.render(scene, 64, 36, dtype="float32")
    assert bright[..., :3].mean() > dark[..., :3].mean() * 1.5
    assert renderer.last_stats["seconds_environment"] > 0.0


def test_render_takes_the_environment_and_gl_materials(tmp_path):
    # A glTF quad without lights: facet's default lighting is the studio for its PBR material, the
    # GL rig with gl_materials=True; environment="none" leaves the PBR material in the dark.
    import base64, json, struct
    positions = struct.pack("<12f", -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0)
    normals = struct.pack("<12f", *([0, 0, 1] * 4))
    indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    blob = positions + normals + indices
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                           {"buffer": 0, "byteOffset": 96, "byteLength": 12}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                         {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                         {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
           "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 0.6}}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}]}
    path = tmp_path / "quad.gltf"
    path.write_text(json.dumps(doc))
    studio = facet.render(str(path), 32, 18, threads=1)
    dark = facet.render(str(path), 32, 18, threads=1, environment="none")
    gl = facet.render(str(path), 32, 18, threads=1, gl_materials=True)
    assert studio[..., :3].mean() > 40
    assert dark[..., :3].max() == 0
    assert gl[..., :3].mean() > 40 and (gl != studio).any()


def test_background_draws_the_surroundings_behind_the_model():
    scene = pbr_sphere_scene()
    assert scene.background == "colour"
    with pytest.raises(facet.Error, match="background"):
        scene.background = "sky"
    renderer = facet.Renderer(threads=1, shading="phong")
    sky = np.zeros((8, 16, 3), dtype=np.float32)
    sky[:4] = (0.2, 0.4, 0.9)  # above the horizon
    sky[4:] = (0.3, 0.2, 0.1)
    scene.set_environment(sky)
    plain = renderer.render(scene, 64, 36, dtype="float32")
    scene.background = "environment"
    assert scene.background == "environment"
    behind = renderer.render(scene, 64, 36, dtype="float32")
    assert (behind[..., 3] == 1.0).all()  # opaque everywhere
    corner = behind[0, 0, :3]
    assert corner[2] > corner[0] and not np.allclose(corner, plain[0, 0, :3])
    scene.set_environment("none")
    with pytest.raises(facet.Error, match="background"):
        renderer.render(scene, 64, 36)
