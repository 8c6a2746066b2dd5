"""Cameras from Python: orthographic projection, framing options, a file's camera by name."""
import math
import os

import numpy as np
import pytest

import facet

DATA = os.environ.get("FACET_DATA", os.path.join(os.path.dirname(__file__), "..", "data"))
CAMERAS = os.path.join(DATA, "gltf", "two_cameras.gltf")


def quad_at(z):
    scene = facet.Scene(empty=True)
    positions = np.array([[-1, -1, z], [1, -1, z], [1, 1, z], [-1, 1, z]], dtype=np.float32)
    mesh = scene.add_mesh(positions, np.array([[0, 1, 2], [0, 2, 3]]))
    material = scene.add_material(emissive=(1, 0, 0), ambient=(0, 0, 0), diffuse=(0, 0, 0))
    scene.add_object(mesh, material)
    return scene


def test_orthographic_camera_keeps_size_at_every_depth():
    renderer = facet.Renderer(threads=1)
    covered = []
    for z in (-3.0, -30.0):
        scene = quad_at(z)
        scene.set_camera(eye=(0, 0, 0), target=(0, 0, -1), projection="orthographic", half_height=2.0, near=0.0, far=50.0)
        assert scene.camera["projection"] == "orthographic"
        assert scene.camera["half_height"] == 2.0
        covered.append(int((renderer.render(scene, 32, 32)[..., 0] > 0).sum()))
    assert covered == [256, 256]


def test_set_camera_refuses_what_a_box_cannot_be_and_keeps_the_camera():
    scene = quad_at(-3.0)
    before = scene.camera
    for kwargs in ({"half_height": 0.0}, {"far": math.inf}, {"near": -1.0}, {"half_height": math.nan}):
        with pytest.raises(facet.Error):
            scene.set_camera(eye=(0, 0, 0), target=(0, 0, -1), projection="orthographic", **kwargs)
    with pytest.raises(facet.Error, match="projection"):
        scene.set_camera(eye=(0, 0, 0), target=(0, 0, -1), projection="fisheye\x1b")
    assert scene.camera == before


def test_frame_takes_view_up_fov_and_projection():
    scene = quad_at(-3.0)
    scene.frame(aspect=1.0, view=(90, 0), up="z", projection="orthographic", fill=0.5)
    cam = scene.camera
    assert cam["projection"] == "orthographic"
    assert cam["up"] == [0.0, 0.0, 1.0]
    scene.frame(aspect=1.0, up="-y", fov_deg=30)
    assert scene.camera["projection"] == "perspective" and scene.camera["fov_deg"] == 30.0
    assert scene.camera["up"] == [0.0, -1.0, 0.0]
    scene.orbit(45, up="-y")
    for bad in ({"up": "w"}, {"projection": "fisheye"}, {"view": (0, 90)}, {"fov_deg": 180}):
        with pytest.raises(facet.Error):
            scene.frame(aspect=1.0, **bad)


def test_load_picks_a_files_camera_by_name_and_lists_them():
    scene = facet.load(CAMERAS)
    assert scene.camera["projection"] == "perspective"
    assert scene.cameras == ["0 'Front' (node 'FrontCam'), perspective", "1 'Top' (node 'TopCam'), orthographic"]
    top = facet.load(CAMERAS, camera="Top")
    assert top.camera["projection"] == "orthographic" and top.camera["half_height"] == 1.5
    assert facet.load(CAMERAS, camera="1").camera == top.camera
    with pytest.raises(facet.Error, match="no camera 'Side'"):
        facet.load(CAMERAS, camera="Side")
    with pytest.raises(facet.Error, match="camera"):
        facet.load(CAMERAS, camera="Top", projection="orthographic")
    framed = facet.load(CAMERAS, projection="orthographic", view=(30, 20))
    assert framed.camera["projection"] == "orthographic"
    assert framed.camera["eye"] != top.camera["eye"]


def test_non_finite_positions_normals_and_uvs_are_refused_by_row():
    scene = facet.Scene(empty=True)
    good = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
    for kwargs, field in (({"positions": np.array([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]])}, "positions[1]: NaN"),
                          ({"positions": good, "normals": np.array([[0, 0, 1], [0, 0, 1], [0, 0, np.inf]])}, "normals[2]: an infinity"),
                          ({"positions": good, "uvs": np.array([[0, 0], [np.nan, 0], [0, 1]])}, "uvs[1]: NaN")):
        with pytest.raises(facet.Error, match=field.replace("[", r"\[").replace("]", r"\]")):
            scene.add_mesh(triangles=np.array([[0, 1, 2]]), **kwargs)
    assert scene.add_mesh(good, np.array([[0, 1, 2]])) == 0


def test_auto_shading_lights_a_model_per_pixel_and_a_scene_file_per_vertex():
    model = os.path.join(DATA, "gltf", "relief_cube.gltf")  # a normal map: lit per pixel only
    auto = facet.render(model, width=64, height=36, threads=1)
    assert (auto == facet.render(model, width=64, height=36, threads=1, shading="phong")).all()
    assert (auto != facet.render(model, width=64, height=36, threads=1, shading="gouraud")).any()
    assert (facet.render(width=64, height=36, threads=1) == facet.render(width=64, height=36, threads=1, shading="gouraud")).all()
    with pytest.raises(facet.Error, match="shading"):
        facet.Renderer(shading="per-pixel")


STRIP = os.path.join(DATA, "gltf", "bending_strip.gltf")


def test_an_animated_model_is_posed_by_index_name_and_time():
    scene = facet.load(STRIP)
    assert [a["name"] for a in scene.animations] == ["bend", "puff"]
    assert scene.animations[1]["end_s"] == 2.0
    renderer = facet.Renderer(threads=1)
    rest = renderer.render(scene, 96, 96).tobytes()
    scene.pose("bend", 1.0)
    bent = renderer.render(scene, 96, 96).tobytes()
    assert bent != rest
    scene.pose(0, 5.0)  # clamped to the last key
    assert renderer.render(scene, 96, 96).tobytes() == bent
    scene.pose(None)
    assert renderer.render(scene, 96, 96).tobytes() == rest
    with pytest.raises(facet.Error, match="no animation 'walk'"):
        scene.pose("walk")
    with pytest.raises(facet.Error, match="out of range"):
        scene.pose(7)
    with pytest.raises(facet.Error, match="finite"):
        scene.pose(0, float("nan"))
    with pytest.raises(facet.Error, match="not loaded from a model that moves"):
        facet.Scene().pose(0)
