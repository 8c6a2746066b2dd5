"""Sweeps (facet.sweep on a local Dask cluster, and the Slurm job-array recipe) against one run of
`facet render --frames`: the same bytes, nothing lost when a worker dies mid-job."""
import filecmp
import json
import os
import subprocess
import sys

import pytest

FACET_BIN = os.environ.get("FACET_BIN", "build/bin/facet")
SOURCE = os.environ.get("FACET_SOURCE", os.path.join(os.path.dirname(__file__), "..", ".."))
MODEL = os.path.join(SOURCE, "tests", "data", "gltf", "tetrahedron_camera.gltf")
SIZE = ["--width", "64", "--height", "36"]
FRAMES = 6


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("reference")
    subprocess.run([FACET_BIN, "render", MODEL, "--frames", str(FRAMES), "-o", str(out / "turn.png")] + SIZE, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return out


def sweep(out, *options):
    command = [sys.executable, "-m", "facet.sweep", MODEL, "-o", str(out), "--facet", FACET_BIN] + list(options)
    return subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=240)


def same_frames(a, b):
    for k in range(FRAMES):
        name = "turn_%04d.png" % k
        assert (b / name).exists(), name
        assert filecmp.cmp(a / name, b / name, shallow=False), name


def test_a_turntable_on_two_workers_is_the_same_bytes(reference, tmp_path):
    result = sweep(tmp_path, "--frames", str(FRAMES), "--workers", "2", "--", *SIZE)
    assert result.returncode == 0, result.stderr
    same_frames(reference, tmp_path)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["ok"] == FRAMES and summary["failed"] == 0
    assert all(r["record"]["context"]["facet_version"] for r in summary["rows"])
    assert (tmp_path / "summary.csv").read_text().count("\n") == FRAMES + 1


def test_a_worker_killed_mid_job_loses_no_frame(reference, tmp_path):
    result = sweep(tmp_path, "--frames", str(FRAMES), "--workers", "2", "--kill-worker-once-at", "frame-0002", "--", *SIZE)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / ".killed-frame-0002").exists()  # the worker running frame 2 did die
    killed_pid = int((tmp_path / ".killed-frame-0002").read_text())
    same_frames(reference, tmp_path)
    rows = json.loads((tmp_path / "summary.json").read_text())["rows"]
    assert [r["status"] for r in rows] == ["ok"] * FRAMES
    assert rows[2]["pid"] != killed_pid  # frame 2 finished on another worker


def test_a_failing_job_is_retried_and_reported_not_lost(tmp_path):
    # Exposure -30 turns the model black on black: facet says nothing shows (exit status 1), which
    # a retry might not repeat (a cluster's fault), so it is retried, then reported.
    result = sweep(tmp_path, "--frames", "2", "--workers", "1", "--retries", "1", "--exposure=-30", *SIZE)
    assert result.returncode == 1, result.stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["failed"] == 2 and "exited 1" in summary["rows"][0]["error"]
    assert "background colour" in summary["rows"][0]["error"]


def test_a_refused_job_stops_the_sweep_with_facets_message(tmp_path):
    result = sweep(tmp_path, "--frames", "6", "--workers", "1", "--", "--width", "0")
    assert result.returncode == 2
    assert "was refused" in result.stderr and "--width" in result.stderr
    rows = json.loads((tmp_path / "summary.json").read_text())["rows"]
    assert rows[0]["status"] == "refused" and "--width" in rows[0]["error"]
    assert all(r["status"] in ("refused", "failed") for r in rows)


def test_a_grid_into_a_new_folder_with_render_options_given_directly(tmp_path):
    out = tmp_path / "new" / "folder"
    result = sweep(out, "--grid", "shading=flat,phong", "--seconds", "0.01", *SIZE)
    assert result.returncode == 0, result.stderr
    rows = json.loads((out / "summary.json").read_text())["rows"]
    assert [r["record"]["width"] for r in rows] == [64, 64] and [r["record"]["shading"] for r in rows] == ["flat", "phong"]


def test_a_turntable_of_one_frame(tmp_path):
    result = sweep(tmp_path, "--frames", "1", *SIZE)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "turn_0000.png").exists()


def test_a_parameter_grid(tmp_path):
    result = sweep(tmp_path, "--grid", "pow=auto,exact", "--grid", "threads=1,2", "--seconds", "0.01", "--", *SIZE)
    assert result.returncode == 0, result.stderr
    rows = json.loads((tmp_path / "summary.json").read_text())["rows"]
    assert [r["key"] for r in rows] == ["pow=auto,threads=1", "pow=auto,threads=2", "pow=exact,threads=1", "pow=exact,threads=2"]
    for r in rows:
        ctx = r["record"]["context"]
        assert ctx["pow"] == r["key"].split(",")[0].split("=")[1] and ctx["threads"] == int(r["key"][-1])
        assert r["record"]["frame_seconds"]["count"] >= 1


def test_the_slurm_array_recipe_splits_the_same_turntable(reference, tmp_path):
    recipe = os.path.join(SOURCE, "tools", "slurm", "turntable.sbatch")
    env = dict(os.environ, FACET=FACET_BIN, SLURM_ARRAY_TASK_MIN="0", SLURM_ARRAY_TASK_MAX="3")
    for task in range(4):  # 6 frames over 4 tasks: 1, 2, 1, 2
        env["SLURM_ARRAY_TASK_ID"] = str(task)
        subprocess.run(["bash", recipe, MODEL, str(tmp_path), str(FRAMES)] + SIZE, check=True, env=env, stdout=subprocess.DEVNULL)
    same_frames(reference, tmp_path)
