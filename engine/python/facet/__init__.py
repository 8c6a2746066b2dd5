"""facet: a CPU rendering engine; pictures as NumPy arrays.

    import facet
    image = facet.render()                              # the built-in scene, 640 x 360, H x W x 4 uint8
    image = facet.render("model.glb", width=640, height=360)

facet.Renderer renders a facet.Scene (facet.load) with its own threads and options, releasing the
GIL; facet.light measures vertex lighting throughput; facet.Error carries facet's message, its
.code and .field. docs/python.md in the facet repository describes it all.
"""
from ._facet import Error, Renderer, Scene, __version__, best_isa, fields, light, load

__all__ = ["Error", "Renderer", "Scene", "__version__", "best_isa", "fields", "light", "load", "render"]


def render(path=None, width=640, height=360, *, shading="auto", msaa=1, srgb=True, threads=0,
           dtype="uint8", allow_paths=(), orbit_deg=0.0, pixel_precision="auto", exposure=None,
           tone_mapping=None, strict=False, gl_materials=False, environment=None, background=None):
    """The picture of a scene file or model (or, with no path, the built-in scene), as `facet
    render` draws it: an H x W x 4 array (uint8, sRGB-encoded unless srgb=False; float32 linear
    light with dtype="float32"). exposure (stops or "auto") and tone_mapping ("none", "neutral",
    "aces") replace the scene's own (docs/color.md). shading "auto" lights a model per pixel
    (Phong) and a scene file per vertex (Gouraud), as `facet render` does. gl_materials=True
    lights glTF materials with GL's model (`facet --gl-materials`); environment ("studio", "none",
    a picture's file name or an H x W x 3 array) replaces what PBR materials see around them
    (`facet --environment-image`, docs/pbr.md); background ("colour" or "environment") what is
    drawn behind the model (`facet --background`)."""
    scene = (load(path, aspect=width / height, allow_paths=list(allow_paths), strict=strict, gl_materials=gl_materials)
             if path is not None else Scene())
    if environment is not None:
        scene.set_environment(environment)
    if background is not None:
        scene.background = background
    if orbit_deg:
        scene.orbit(orbit_deg)
    if exposure is not None or tone_mapping is not None:
        own = scene.display
        scene.set_display(exposure=own["exposure"] if exposure is None else exposure,
                          tone_mapping=own["tone_mapping"] if tone_mapping is None else tone_mapping)
    return Renderer(shading=shading, msaa=msaa, srgb=srgb, threads=threads,
                    pixel_precision=pixel_precision).render(scene, width, height, dtype=dtype)
