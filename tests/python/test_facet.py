"""facet's Python bindings (engine/python), run by ctest through Debian's pytest:

    PYTHONPATH=build/python FACET_BIN=build/bin/facet FACET_DATA=tests/data python3 -m pytest tests/python
"""
import os
import struct
import subprocess
import threading

import numpy as np
import pytest

import facet

FACET_BIN = os.environ.get("FACET_BIN", "build/bin/facet")
DATA = os.environ.get("FACET_DATA", os.path.join(os.path.dirname(__file__), "..", "data"))


def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    magic, dims, scale, pixels = data.split(b"\n", 3)
    assert magic == b"PF"
    w, h = map(int, dims.split())
    a = np.frombuffer(pixels[: w * h * 12], dtype="<f4" if float(scale) < 0 else ">f4").reshape(h, w, 3)
    return a[::-1]  # PFM rows run bottom to top


def in_threads(n, work):
    """work(i) for i in 0..n-1, each on a Python thread of its own, started together; the results in order."""
    results = [None] * n

    def run(i):
        results[i] = work(i)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(n)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return results


def test_render_returns_the_picture_as_an_array():
    image = facet.render(width=64, height=36)
    assert image.shape == (36, 64, 4) and image.dtype == np.uint8
    assert image[0, 0, 3] == 255  # the clear colour's alpha in a corner
    assert image[..., :3].max() > 0  # something is drawn


def test_the_same_picture_as_the_command_line(tmp_path):
    # float32 against `facet render -o x.pfm`: the same floats, so the same renderer and framing.
    out = tmp_path / "cli.pfm"
    subprocess.run([FACET_BIN, "render", "-o", str(out), "--width", "96", "--height", "54"], check=True,
                   stdout=subprocess.DEVNULL)
    mine = facet.render(width=96, height=54, dtype="float32")
    assert mine.dtype == np.float32
    assert np.array_equal(mine[..., :3], read_pfm(out))


def test_a_model_is_framed_and_lit_as_the_command_line_does(tmp_path):
    model = os.path.join(DATA, "gltf", "tetrahedron_camera.gltf")
    out = tmp_path / "model.pfm"
    subprocess.run([FACET_BIN, "render", model, "-o", str(out), "--width", "80", "--height", "60"], check=True,
                   stdout=subprocess.DEVNULL)
    mine = facet.render(model, width=80, height=60, dtype="float32")
    assert np.array_equal(mine[..., :3], read_pfm(out))
    assert facet.load(model).object_count == 1


def test_renders_into_the_callers_array_without_a_copy():
    r = facet.Renderer(threads=1)
    scene = facet.Scene()
    big = np.zeros((40, 100, 4), dtype=np.uint8)
    view = big[:, 10:74, :]  # rows 100 pixels apart: strided rows are fine
    returned = r.render(scene, 64, 40, out=view)
    assert np.shares_memory(returned, big)
    assert big[:, 10:74, :3].max() > 0 and big[:, :10].max() == 0 and big[:, 74:].max() == 0
    assert np.array_equal(view, r.render(scene, 64, 40))
    with pytest.raises(facet.Error) as e:
        r.render(scene, 64, 41, out=view)
    assert e.value.field == "out" and "shape (41, 64, 4)" in str(e.value)
    with pytest.raises(facet.Error):
        r.render(scene, 64, 40, out=np.zeros((40, 64, 4), dtype=np.uint16))
    with pytest.raises(facet.Error):
        r.render(scene, 64, 40, out=np.zeros((40, 64, 4), dtype=np.uint8)[:, ::-1])  # pixels not contiguous


def test_errors_are_facet_errors_with_facets_message(tmp_path):
    with pytest.raises(facet.Error) as e:
        facet.load(str(tmp_path / "missing.json"))
    assert e.value.code == "io_error" and "missing.json" in str(e.value)
    bad = tmp_path / "bad.json"
    bad.write_text('{\n  "materials": [ { "name": "m", "diffuse": "red" } ]\n}\n')
    with pytest.raises(facet.Error) as e:
        facet.load(str(bad))
    assert e.value.code == "parse_error" or e.value.code == "invalid_argument"
    assert "bad.json:2" in str(e.value) and "materials[0].diffuse" in str(e.value)
    # A scene may not read outside its folder unless the caller allows it.
    inside = tmp_path / "inside"
    inside.mkdir()
    (inside / "scene.json").write_text('{"meshes": [{"name": "m", "obj": "../outside.obj"}]}')
    (tmp_path / "outside.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(facet.Error) as e:
        facet.load(str(inside / "scene.json"))
    assert "outside.obj" in str(e.value)
    assert facet.load(str(inside / "scene.json"), allow_paths=[str(tmp_path)]).object_count == 0
    with pytest.raises(facet.Error) as e:
        facet.Renderer(shading="glossy")
    assert e.value.field == "shading"


def test_the_gil_is_released_while_rendering():
    # Python code runs on this thread while another renders a large frame on one thread.
    r = facet.Renderer(shading="phong", msaa=4, threads=1)
    scene = facet.Scene()
    t = threading.Thread(target=lambda: r.render(scene, 1920, 1080))
    t.start()
    steps = 0
    while t.is_alive():
        steps += 1
    t.join()
    assert steps > 1000, steps  # with the GIL held for the whole render, this thread would not run


def test_threads_render_concurrently_to_the_same_bytes():
    scene = facet.Scene()
    expected = facet.Renderer(threads=1).render(scene, 160, 90)
    for image in in_threads(4, lambda i: facet.Renderer(threads=1 + i % 2).render(scene, 160, 90)):
        assert np.array_equal(image, expected)


def test_threads_sharing_one_renderer_take_turns():
    scene = facet.Scene()
    shared = facet.Renderer(threads=2)
    expected = shared.render(scene, 120, 68)
    for image in in_threads(4, lambda i: shared.render(scene, 120, 68)):
        assert np.array_equal(image, expected)


def test_a_scene_built_from_python_objects():
    # A square of two triangles in front of the camera, lit head-on: every covered pixel shows the
    # material's diffuse colour times the light's (n.l = 1, no attenuation, no ambient).
    scene = facet.Scene(empty=True)
    positions = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float64)
    square = scene.add_mesh(positions, np.array([[0, 1, 2], [0, 2, 3]]))
    red = scene.add_material(diffuse=(0.8, 0.2, 0.1), ambient=(0, 0, 0))
    scene.add_object(square, red)
    scene.add_light("directional", direction=(0, 0, -1), diffuse=(1, 1, 1), specular=(0, 0, 0))
    scene.set_camera(eye=(0, 0, 3), target=(0, 0, 0), fov_deg=60)
    image = facet.Renderer(threads=1).render(scene, 32, 32, dtype="float32")
    centre = image[16, 16]
    assert np.allclose(centre[:3], [0.8, 0.2, 0.1], atol=1e-6), centre
    assert scene.object_count == 1 and scene.light_count == 1 and scene.triangle_count == 2
    moved = np.eye(4)
    moved[0, 3] = 5.0  # out of view
    scene.add_object(square, red, transform=moved)
    assert scene.object_count == 2
    with pytest.raises(facet.Error) as e:
        scene.add_mesh(np.zeros((3, 2)), np.array([[0, 1, 2]]))
    assert e.value.field == "positions"
    with pytest.raises(facet.Error) as e:
        scene.add_mesh(positions, np.array([[0, 1, 7]]))  # an index past the positions
    assert "7" in str(e.value)
    with pytest.raises(facet.Error):
        scene.add_object(square, 9)
    with pytest.raises(facet.Error):
        scene.add_material(diffuse=(0.5, float("nan"), 0.5))
    with pytest.raises(facet.Error):
        scene.add_light("area")


def test_a_textured_scene_built_from_python_objects():
    # A 2 x 2 texture (an image, top row first) on a square facing the camera with texture
    # coordinates 0..1, GL_REPLACE: each quarter of the square shows its texel, upright.
    scene = facet.Scene(empty=True)
    positions = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float32)
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=np.float32)
    square = scene.add_mesh(positions, np.array([[0, 1, 2], [0, 2, 3]]), uvs=uvs)
    texels = np.array([[[255, 0, 0, 255], [0, 255, 0, 255]],
                       [[0, 0, 255, 255], [255, 255, 255, 255]]], dtype=np.uint8)
    texture = scene.add_texture(texels, filter="nearest", wrap="clamp")
    material = scene.add_material(diffuse=(0, 0, 0), ambient=(0, 0, 0), texture=texture, texture_mode="replace")
    scene.add_object(square, material)
    scene.set_camera(eye=(0, 0, 3), target=(0, 0, 0), fov_deg=60)
    image = facet.Renderer(threads=1).render(scene, 64, 64, dtype="float32")
    # The square spans 1 / tan(30 deg) / 3 of the half-height: quarter centres about 9 pixels off centre.
    for (row, col), texel in {(22, 22): (1, 0, 0), (22, 41): (0, 1, 0), (41, 22): (0, 0, 1), (41, 41): (1, 1, 1)}.items():
        assert np.array_equal(image[row, col, :3], np.array(texel, dtype=np.float32)), (row, col, image[row, col])
    # Nearest texels are the same in both pixel tiers.
    fast = facet.Renderer(threads=1, pixel_precision="fast").render(scene, 64, 64)
    assert np.array_equal(fast, facet.Renderer(threads=1, pixel_precision="exact").render(scene, 64, 64))
    # Linear fog from 0 to 6 on the square at depth 3: halfway to the fog's colour.
    scene.set_fog("linear", color=(0, 0, 1), start=0, end=6)
    fogged = facet.Renderer(threads=1).render(scene, 64, 64, dtype="float32")
    assert np.allclose(fogged[22, 22, :3], [0.5, 0, 0.5], atol=1e-6), fogged[22, 22]
    scene.set_fog("none")
    assert np.array_equal(facet.Renderer(threads=1).render(scene, 64, 64, dtype="float32"), image)
    for call, field in [(lambda: scene.add_texture(np.zeros((2, 2, 3), dtype=np.uint8)), "pixels"),
                        (lambda: scene.add_texture(texels, filter="cubic"), "filter"),
                        (lambda: scene.add_material(texture=7), "texture"),
                        (lambda: scene.add_material(blend="screen"), "blend"),
                        (lambda: scene.add_material(uv_scale=(0, 1)), ""),
                        (lambda: scene.add_mesh(positions, np.array([[0, 1, 2]]), uvs=np.zeros((4, 3))), "uvs"),
                        (lambda: scene.set_fog("linear", start=5, end=1), ""),
                        (lambda: facet.Renderer(pixel_precision="half"), "pixel_precision")]:
        with pytest.raises(facet.Error) as e:
            call()
        assert field in e.value.field, (field, e.value.field, str(e.value))


def test_stats_camera_and_orbit():
    r = facet.Renderer()
    scene = facet.Scene()
    first = r.render(scene, 80, 45)
    stats = r.last_stats
    assert stats["pixels_filled"] > 0 and stats["triangles_in"] == scene.triangle_count
    scene.orbit(90)
    assert not np.array_equal(r.render(scene, 80, 45), first)
    scene.set_camera(eye=(0, 0, 5), target=(0, 0, 0))
    with pytest.raises(facet.Error):
        scene.set_camera(eye=(0, 0, 0), target=(0, 0, 0))


@pytest.mark.parametrize("path", ["reference", "scalar", "simd"])
def test_light_measures_each_path(path):
    result = facet.light(lighting_path=path, seconds=0.02)
    assert result["path"] == path
    assert result["vertices"] > 0 and result["vertices_per_second"] > 0
    assert result["isa"] == (facet.best_isa() if path == "simd" else "none")
