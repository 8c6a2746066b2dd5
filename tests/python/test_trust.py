"""What a Python caller cannot break: a scene changed while another thread renders it (refused,
never a crash), values that NumPy would cast in silence (refused), each keyword that changes the
picture it names, and facet.sweep's options (no folder escape, no hang, a time limit)."""
import json
import os
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import facet

FACET_BIN = os.environ.get("FACET_BIN", "build/bin/facet")
SOURCE = os.environ.get("FACET_SOURCE", os.path.join(os.path.dirname(__file__), "..", ".."))
MODEL = os.path.join(SOURCE, "tests", "data", "gltf", "tetrahedron_camera.gltf")

TRI = np.array([[0, 1, 2]])
POS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)


def big_scene():
    scene = facet.Scene(empty=True)
    n = 200
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    pos = np.stack([u.ravel(), v.ravel(), np.zeros(n * n)], axis=1).astype(np.float32)
    quads = [(i * n + j, i * n + j + 1, (i + 1) * n + j + 1) for i in range(n - 1) for j in range(n - 1)]
    mesh = scene.add_mesh(pos, np.array(quads, dtype=np.uint32))
    material = scene.add_material()
    for k in range(20):
        t = np.eye(4)
        t[0, 3] = 0.01 * k
        scene.add_object(mesh, material, t)
    scene.add_light(type="directional", direction=[0, 0, -1])
    scene.set_camera(eye=[0.5, 0.5, 2], target=[0.5, 0.5, 0])
    return scene


def test_a_scene_changed_while_it_is_rendered_is_refused_not_crashed():
    scene = big_scene()
    renderer = facet.Renderer(shading="phong", threads=2)
    stop = threading.Event()
    refused, changed, errors = [0], [0], []

    def render():
        try:
            while not stop.is_set():
                renderer.render(scene, 320, 240)
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(e)

    def mutate():
        for _ in range(400):
            for call in (lambda: scene.add_mesh(POS, TRI), lambda: scene.add_object(0, 0),
                         lambda: scene.add_light(), lambda: scene.orbit(1.0)):
                try:
                    call()
                    changed[0] += 1
                except facet.Error as e:
                    assert e.field == "scene" and "being rendered" in str(e)
                    refused[0] += 1
            time.sleep(0.0005)

    threads = [threading.Thread(target=render) for _ in range(2)] + [threading.Thread(target=mutate)]
    for t in threads:
        t.start()
    threads[2].join()
    stop.set()
    for t in threads[:2]:
        t.join()
    assert not errors, errors
    assert refused[0] > 0, "the renders never overlapped a change: the test did not test"
    # Once no render runs, the scene can be changed again.
    scene.add_light()


@pytest.mark.parametrize("triangles, bad", [
    (np.array([[0, 1, 2 ** 32 + 1]], dtype=np.int64), "4294967297"),
    (np.array([[0, 1, -1]], dtype=np.int64), "-1"),
    (np.array([[0, 1, 2.5]]), "2.5"),
    (np.array([[0, 1, np.nan]]), "nan"),
    (np.array([["0", "1", "2"]]), "numbers"),
])
def test_indices_that_do_not_convert_exactly_are_refused(triangles, bad):
    scene = facet.Scene(empty=True)
    with pytest.raises(facet.Error) as e:
        scene.add_mesh(POS, triangles)
    assert e.value.field == "triangles" and bad in str(e.value)
    # Exact values of any integer or float dtype are taken.
    for dtype in (np.int64, np.uint16, np.float64):
        assert scene.add_mesh(POS, TRI.astype(dtype)) >= 0


@pytest.mark.parametrize("value, bad", [(300.7, "300.7"), (-1, "-1"), (256, "256"), (0.5, "0.5")])
def test_texels_that_do_not_convert_exactly_are_refused(value, bad):
    scene = facet.Scene(empty=True)
    pixels = np.full((2, 2, 4), 7.0)
    pixels[1, 1, 0] = value
    with pytest.raises(facet.Error) as e:
        scene.add_texture(pixels)
    assert e.value.field == "pixels" and bad in str(e.value)
    assert scene.add_texture(np.full((2, 2, 4), 255.0)) == 0
    assert scene.add_texture(np.full((2, 2, 4), 9, dtype=np.int32)) == 1


def test_a_float_out_array_gets_floats_whatever_dtype_says():
    scene = facet.Scene()
    renderer = facet.Renderer(threads=1)
    u8 = facet.Renderer(threads=1, srgb=False).render(scene, 64, 36)
    out = np.zeros((36, 64, 4), dtype=np.float32)
    renderer.render(scene, 64, 36, out=out)  # dtype left at "uint8"
    assert out.max() <= 1.0 and out.max() > 0.1
    assert np.abs(out * 255 - u8).max() <= 1.0


def test_each_renderer_keyword_changes_what_it_names():
    scene = facet.Scene()
    base = facet.Renderer(threads=1).render(scene, 96, 54)
    for kwargs in ({"shading": "flat"}, {"shading": "phong"}, {"msaa": 4}, {"srgb": False},
                   {"clear": [0.5, 0.25, 0.0, 1.0]}):
        image = facet.Renderer(threads=1, **kwargs).render(scene, 96, 54)
        assert not np.array_equal(image, base), kwargs


def test_each_render_keyword_changes_what_it_names():
    base = facet.render(width=96, height=54)
    for kwargs in ({"shading": "flat"}, {"shading": "phong"}, {"msaa": 4}, {"srgb": False}, {"orbit_deg": 30.0},
                   {"exposure": 1.0}, {"exposure": "auto"}, {"tone_mapping": "aces"}):
        assert not np.array_equal(facet.render(width=96, height=54, **kwargs), base), kwargs
    # and those that must not change it do not
    for kwargs in ({"threads": 1}, {"pixel_precision": "exact"}, {"srgb": True}, {"exposure": 0.0},
                   {"tone_mapping": "none"}):
        assert np.array_equal(facet.render(width=96, height=54, **kwargs), base), kwargs
    as_float = facet.render(width=96, height=54, dtype="float32")
    linear = facet.render(width=96, height=54, srgb=False)
    assert as_float.dtype == np.float32 and np.abs(as_float * 255 - linear).max() <= 1.0


def sweep(out, *options, timeout=240):
    command = [sys.executable, "-m", "facet.sweep", MODEL, "-o", str(out), "--facet", FACET_BIN] + list(options)
    return subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)


@pytest.mark.parametrize("options, message", [
    (["--frames", "2", "--name", "../../x.png"], "--name"),
    (["--frames", "2", "--name", "sub/x.png"], "--name"),
    (["--frames", "2", "--workers", "0"], "--workers"),
    (["--frames", "2", "--workers", "-3"], "--workers"),
    (["--frames", "-3"], "--frames"),
    (["--frames", "0"], "--frames"),
    (["--frames", "2", "--retries", "-1"], "--retries"),
    (["--frames", "2", "--time-limit", "0"], "--time-limit"),
])
def test_sweep_options_are_checked(tmp_path, options, message):
    result = sweep(tmp_path / "out", *options, timeout=60)
    assert result.returncode == 2, result.stderr
    assert message in result.stderr
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "out" / "summary.json").exists()


def test_a_sweep_runs_each_frame_once(tmp_path):
    result = sweep(tmp_path, "--frames", "3", "--workers", "1", "--", "--width", "32", "--height", "18")
    assert result.returncode == 0, result.stderr
    rows = json.loads((tmp_path / "summary.json").read_text())["rows"]
    # Each job's record is its own turntable summary: one frame each.
    assert [r["record"]["frames"] for r in rows] == [1, 1, 1], [r["record"] for r in rows]
    assert sorted(os.listdir(tmp_path)) == ["summary.csv", "summary.json", "turn_0000.png", "turn_0001.png", "turn_0002.png"]


def test_a_sweep_stops_at_its_time_limit(tmp_path):
    started = time.time()
    # Each grid point renders for 60 s: the sweep's 5-second limit stops them all.
    result = sweep(tmp_path, "--grid", "threads=1,1", "--seconds", "60", "--time-limit", "5", "--workers", "1", "--",
                   "--width", "32", "--height", "18", timeout=120)
    took = time.time() - started
    assert result.returncode == 1, result.stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["failed"] == 2
    assert all("time limit" in r["error"] for r in summary["rows"]), summary["rows"]
    assert took < 60, took
