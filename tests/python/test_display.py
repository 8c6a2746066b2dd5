"""Exposure, tone mapping and sRGB output from Python (docs/color.md)."""
import numpy as np
import pytest

import facet


def test_output_is_srgb_by_default_and_linear_on_request():
    srgb = facet.render(width=64, height=36, threads=1)
    linear = facet.render(width=64, height=36, threads=1, srgb=False)
    floats = facet.render(width=64, height=36, threads=1, dtype="float32")
    # Where the linear value is mid-grey, the encoded byte is brighter (0.5 -> 188).
    lit = linear[..., :3] > 20
    assert lit.sum() > 500
    assert (srgb[..., :3][lit].astype(int) >= linear[..., :3][lit]).all()
    assert (srgb[..., :3][lit].astype(int) > linear[..., :3][lit]).mean() > 0.9
    assert np.abs(floats[..., :3] * 255 - linear[..., :3]).max() <= 1.0


def test_set_display_validates_and_reads_back():
    scene = facet.Scene()
    assert scene.display == {"exposure": 0.0, "tone_mapping": "none"}
    scene.set_display(exposure="auto", tone_mapping="aces")
    assert scene.display == {"exposure": "auto", "tone_mapping": "aces"}
    scene.set_display(exposure=-1.5, tone_mapping="neutral")
    assert scene.display == {"exposure": -1.5, "tone_mapping": "neutral"}
    for exposure, tone in ((99, "none"), ("bright", "none"), (0, "reinhard"), ([1], "none")):
        with pytest.raises(facet.Error):
            scene.set_display(exposure=exposure, tone_mapping=tone)
    assert scene.display == {"exposure": -1.5, "tone_mapping": "neutral"}


def test_plus_one_stop_doubles_hdr_float_output_and_auto_is_reported():
    scene = facet.Scene()
    renderer = facet.Renderer(threads=1)
    scene.set_display(exposure=-1.0, tone_mapping="neutral")
    out = np.zeros((36, 64, 4), dtype=np.float32)
    # Float output without HDR is tone-mapped into [0, 1]; compare the exposure on the metered value.
    scene.set_display(exposure="auto", tone_mapping="neutral")
    renderer.render(scene, 64, 36, out=out)
    ev = renderer.last_stats["exposure_ev"]
    assert -30.0 <= ev <= 30.0 and ev != 0.0
    assert out.max() <= 1.0
    scene.set_display(exposure=ev, tone_mapping="neutral")
    fixed = renderer.render(scene, 64, 36, dtype="float32")
    assert renderer.last_stats["exposure_ev"] == pytest.approx(ev)
    assert np.array_equal(fixed, out)


def test_render_takes_exposure_and_tone_mapping():
    base = facet.render(width=64, height=36, threads=1)
    brighter = facet.render(width=64, height=36, threads=1, exposure=1.0)
    mapped = facet.render(width=64, height=36, threads=1, tone_mapping="aces")
    assert brighter[..., :3].astype(int).sum() > base[..., :3].astype(int).sum()
    assert not np.array_equal(mapped, base)


def test_load_warns_of_missing_files_unless_strict(tmp_path):
    (tmp_path / "m.obj").write_text("mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n")
    scene = facet.load(str(tmp_path / "m.obj"))
    assert any("gone.mtl" in w for w in scene.warnings)
    with pytest.raises(facet.Error) as e:
        facet.load(str(tmp_path / "m.obj"), strict=True)
    assert "gone.mtl" in str(e.value)
    assert facet.render(str(tmp_path / "m.obj"), width=32, height=18).shape == (18, 32, 4)
    with pytest.raises(facet.Error):
        facet.render(str(tmp_path / "m.obj"), width=32, height=18, strict=True)
