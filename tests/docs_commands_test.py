#!/usr/bin/env python3
"""Runs every facet command the README and docs/ show in their code blocks, so that they cannot
drift from the program (a missing -o, a renamed option, a file that needs --allow-path).

    docs_commands_test.py FACET SOURCE WORK [PYTHONPATH]

Commands are the lines of ``` blocks that start with `facet ` or `build/bin/facet ` (and
`python3 -m facet.sweep ` when PYTHONPATH holds the bindings), and whole commands quoted in the
text (`facet render|check|bake|light` with a .json, .gltf, .glb or .obj file). Synopses (with [ ] or |), printed
output (`facet render: ...`) and C++ are not commands. Each runs in WORK, where the names the docs
use stand for small real files: model.glb, model.gltf, model.obj, animated.glb, scene.json, and the repository's
tests/data. Every command must exit 0 (bakes run with at most 2000 radiosity shots: the README's
bake of the Cornell box takes 90 s to converge, and what is checked here is its options and files). Not run: tools/run and tools/test (CI runs tools/test
itself, and tools/run's render is the built-in scene's), tools/charts (minutes of benchmarks),
tools/cornell-pathtraced (Embree path tracing, minutes) and tools/data/*.py (they write the
repository's own test data).
"""
import glob
import json
import os
import re
import shlex
import shutil
import struct
import subprocess
import sys

COMMAND = re.compile(r"^(build/bin/facet|facet|python3 -m facet\.sweep)( |$)")
INLINE = re.compile(r"`((?:build/bin/)?facet (?:render|check|bake|light) [^`]*?\.(?:json|gltf|glb|obj)\b[^`]*)`")


def commands(source):
    found = []
    for doc in ["README.md"] + sorted(glob.glob(os.path.join(source, "docs", "*.md"))):
        path = doc if os.path.isabs(doc) else os.path.join(source, doc)
        in_block = False
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                if line.startswith("```"):
                    in_block = not in_block
                    continue
                if not in_block:  # a whole command in running text: `facet render FILE ...`
                    for text in INLINE.findall(line):
                        if not re.search(r"[A-Z]{2,}|\.\.\.|[\[\]|]", text):  # not a synopsis (FILE, DIR, [..])
                            found.append((os.path.relpath(path, source), number, text))
                    continue
                text = line.split(" #")[0].strip()
                if not COMMAND.match(text):
                    continue
                if "[" in text or "|" in text or re.match(r"^(build/bin/)?facet [a-z-]+:", text):
                    continue  # a synopsis, or a line of output
                found.append((os.path.relpath(path, source), number, text))
    unique = []
    for item in found:  # the same command shown twice runs once
        if item[2] not in [u[2] for u in unique]:
            unique.append(item)
    return unique


def glb_from_gltf(gltf_path, glb_path):
    """A .glb of a .gltf whose one buffer is a data: URI."""
    import base64

    doc = json.load(open(gltf_path))
    data = base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1])
    del doc["buffers"][0]["uri"]
    doc["buffers"][0]["byteLength"] = len(data)
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    data += b"\0" * (-len(data) % 4)
    with open(glb_path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(data)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        f.write(struct.pack("<II", len(data), 0x004E4942) + data)


def prepare(source, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    shutil.copytree(os.path.join(source, "tests", "data"), os.path.join(work, "tests", "data"))
    data = os.path.join(source, "tests", "data")
    glb_from_gltf(os.path.join(data, "gltf", "tetrahedron_camera.gltf"), os.path.join(work, "model.glb"))
    glb_from_gltf(os.path.join(data, "gltf", "bending_strip.gltf"), os.path.join(work, "animated.glb"))
    shutil.copy(os.path.join(data, "gltf", "relief_cube.gltf"), os.path.join(work, "model.gltf"))
    shutil.copy(os.path.join(data, "obj", "tetrahedron.obj"), os.path.join(work, "model.obj"))
    scene = json.load(open(os.path.join(data, "scenes", "example.json")))
    scene["meshes"] = [m for m in scene["meshes"] if "obj" not in m]  # shapes only: the file stands alone
    scene["objects"] = [o for o in scene["objects"] if o["mesh"] in {m["name"] for m in scene["meshes"]}]
    with open(os.path.join(work, "scene.json"), "w") as f:
        json.dump(scene, f)
    os.makedirs(os.path.join(work, "d"))
    shutil.copy(os.path.join(work, "scene.json"), os.path.join(work, "d", "scene.json"))
    # The animated model the README shows: assimp's test model BCN_Epileptic.X converted to glTF by
    # assimp (Debian's assimp-testmodels and assimp-utils; tools/test installs them).
    if shutil.which("assimp") and os.path.exists(BCN_SOURCE):
        subprocess.run(["assimp", "export", BCN_SOURCE, os.path.join(work, "BCN_Epileptic.glb")], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


BCN_SOURCE = "/usr/share/assimp/models/X/BCN_Epileptic.X"


# Commands the docs show being refused, with the status they must exit with.
REFUSED = {"facet bake d/scene.json -o d --overwrite": 2}
# Commands on the models beside the checkout (../shared/models), which the repository does not hold.
NEEDS_MODELS = ("bunny.json", "shared/models")


def main():
    facet, source, work = sys.argv[1:4]
    env = dict(os.environ)
    if len(sys.argv) > 4 and sys.argv[4]:
        env["PYTHONPATH"] = sys.argv[4]
    prepare(source, work)
    failed = 0
    ran = 0
    for doc, number, text in commands(source):
        words = shlex.split(text)
        if words[0] in ("facet", "build/bin/facet"):
            argv = [facet] + words[1:]
            if words[1] == "bake":
                # The options and files are checked, not the light: at most 2000 shots of radiosity
                # (a fixed amount of work, not a time limit, which a loaded machine could run out).
                if "--max-shots" in argv:
                    i = argv.index("--max-shots") + 1
                    argv[i] = str(min(int(argv[i]), 2000))
                else:
                    argv += ["--max-shots", "2000"]
        elif "PYTHONPATH" in env:
            argv = [sys.executable, "-m", "facet.sweep"] + words[3:] + ["--facet", facet]
        else:
            print("skipped (no Python bindings): %s:%d: %s" % (doc, number, text))
            continue
        if any(m in text for m in NEEDS_MODELS):
            print("skipped (needs ../shared/models): %s:%d: %s" % (doc, number, text))
            continue
        if "BCN_Epileptic.glb" in text and not os.path.exists(os.path.join(work, "BCN_Epileptic.glb")):
            failed += 1
            print("FAILED: %s:%d: %s\n  needs BCN_Epileptic.glb, made from %s by assimp: install assimp-testmodels "
                  "and assimp-utils (tools/test does)" % (doc, number, text, BCN_SOURCE))
            continue
        result = subprocess.run(argv, cwd=work, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                timeout=600)
        ran += 1
        if result.returncode != REFUSED.get(text, 0):
            failed += 1
            print("FAILED (exit %d): %s:%d: %s\n%s" % (result.returncode, doc, number, text, result.stdout[-2000:]))
        else:
            print("ok: %s:%d: %s" % (doc, number, text))
    print("%d commands run, %d failed" % (ran, failed))
    return 1 if failed or ran == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
