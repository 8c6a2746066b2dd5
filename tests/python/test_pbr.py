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
