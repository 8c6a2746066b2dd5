#!/usr/bin/env bash
# facet bake and the files it reads and writes: it copies exactly the files the loader read (a
# canary outside the model's folder, reachable five ways the loader never reads, is never
# copied), writes only into a new or empty folder (or --overwrite), never through a link, never
# over its input; a FIFO named by a model never blocks it; its time limit holds in every phase;
# its lightmaps never take the name of the scene's own texture.
#   usage: bake_files_test.sh FACET DATA_DIR WORKDIR
set -u
facet="$1" data="$2" work="$3"
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
failed=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAILED: $1"; failed=1; fi; }
no_canary() { ! grep -rqs CANARY "$1"; }
quick=(--texels-per-unit 8 --max-shots 50 --rays 16 --burial-rays 0)

mkdir -p outside/dir model/sub
echo CANARY > outside/canary.png
echo CANARY > outside/dir/canary.png
"$facet" render -o model/sub/t.png --width 4 --height 4 >/dev/null 2>&1 || echo "FAILED: a texture to read"

# 1. A glTF with unused images (not read by the loader): a link out, one under a linked folder,
# the same percent-encoded.
ln -s ../outside/canary.png model/link.png
ln -s ../outside/dir model/dir
python3 - "$data/gltf/tetrahedron_camera.gltf" model/m.gltf <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
d["images"] = [{"uri": "link.png"}, {"uri": "dir/canary.png"}, {"uri": "d%69r/canary.png"}]
json.dump(d, open(sys.argv[2], "w"))
EOF
out=$("$facet" bake model/m.gltf -o b1 "${quick[@]}" 2>&1); rc=$?
check "a glTF with unused images that lead out bakes (exit $rc: $out)" '[ $rc -eq 0 ] && [ -f b1/scene.json ]'
check "  and nothing outside its folder is copied" 'no_canary b1 && [ ! -e b1/import_0/link.png ] && [ ! -e b1/import_0/dir ]'
out=$("$facet" render b1/scene.json -o b1.png --width 32 --height 32 2>&1); rc=$?
check "  and the baked scene renders (exit $rc: $out)" '[ $rc -eq 0 ]'

# 2. An OBJ whose MTL (in sub/) names t.png beside itself, map_Ks and refl links out (the loader
# reads neither), and a t.png beside the OBJ that is not the one the MTL means.
ln -s ../../outside/canary.png model/sub/spec.png
ln -s ../../outside/canary.png model/sub/refl.png
echo CANARY > model/t.png
printf 'newmtl m\nKd 1 1 1\nmap_Kd t.png\nmap_Ks spec.png\nrefl -type sphere refl.png\n' > model/sub/m.mtl
printf 'mtllib sub/m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n' > model/m.obj
out=$("$facet" bake model/m.obj -o b2 "${quick[@]}" 2>&1); rc=$?
check "an OBJ whose MTL names files it does not use bakes (exit $rc: $out)" '[ $rc -eq 0 ] && [ -f b2/scene.json ]'
check "  and copies the texture the MTL meant (sub/t.png), nothing else" 'cmp -s b2/import_0/sub/t.png model/sub/t.png && no_canary b2 && [ ! -e b2/import_0/t.png ]'
out=$("$facet" render b2/scene.json -o b2.png --width 32 --height 32 2>&1); rc=$?
check "  and the baked scene renders with its texture (exit $rc: $out)" '[ $rc -eq 0 ]'

# 3. The output folder: not empty without --overwrite; never over the input; never through links.
mkdir -p full && echo keep > full/x
out=$("$facet" bake model/m.obj -o full "${quick[@]}" 2>&1); rc=$?
check "a folder that is not empty is refused (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"not empty"* ]] && [ "$(ls full)" = x ]'
mkdir -p scene && cp "$data/cornell/cornell.json" scene/scene.json && cp "$data/cornell/cornell_box.obj" scene/ && cp scene/scene.json scene/orig.json
out=$("$facet" bake scene/scene.json -o scene --texels-per-unit 0.03 --max-shots 50 --rays 16 --burial-rays 0 2>&1); rc=$?
check "baking a scene into its own folder is refused (exit $rc: $out)" '[ $rc -eq 2 ] && cmp -s scene/scene.json scene/orig.json'
out=$("$facet" bake scene/scene.json -o scene --overwrite --texels-per-unit 0.03 --max-shots 50 --rays 16 --burial-rays 0 2>&1); rc=$?
check "  and with --overwrite too: never over the input (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"reads"* ]] && cmp -s scene/scene.json scene/orig.json'
echo target > outside/target
for link in scene.json bake.json lightmap_0.png lightmap_0.exr import_0; do
  rm -rf l && mkdir l
  if [ "$link" = import_0 ]; then ln -s ../outside/dir l/import_0; else ln -s ../outside/target "l/$link"; fi
  out=$("$facet" bake model/m.obj -o l --overwrite "${quick[@]}" 2>&1); rc=$?
  check "a link l/$link is refused, not written through (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"symbolic link"* ]] && [ "$(cat outside/target)" = target ] && [ ! -e outside/dir/m.obj ]'
done
out=$("$facet" bake model/m.obj -o b2 --overwrite "${quick[@]}" 2>&1); rc=$?
check "--overwrite replaces an earlier bake (exit $rc: $out)" '[ $rc -eq 0 ]'

# 4. A scene importing an OBJ (allow_missing) whose mtllib is a FIFO: never blocks.
mkdir -p fifo && mkfifo fifo/m.mtl
printf 'mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > fifo/m.obj
printf '{"imports": [{"file": "m.obj", "allow_missing": true}]}' > fifo/scene.json
out=$(timeout 60 "$facet" bake fifo/scene.json -o b4 "${quick[@]}" 2>&1); rc=$?
check "a FIFO named by an import never blocks the bake (exit $rc: $out)" '[ $rc -eq 0 ] && [ -f b4/scene.json ] && [ ! -e b4/import_0/m.mtl ]'

# 5. Options: --max-shots refuses a negative count.
out=$("$facet" bake model/m.obj -o b5 --max-shots -1 2>&1); rc=$?
check "--max-shots -1 is refused (exit $rc: $out)" '[ $rc -ne 0 ] && [[ "$out" == *"--max-shots"* ]] && [ ! -e b5 ]'

# 6. The time limit holds before the shooting: burial probes of 1024 rays take minutes here.
SECONDS=0
out=$("$facet" bake "$data/cornell/cornell.json" -o b6 --burial-rays 1024 --texels-per-unit 0.1 --seconds 0.5 2>&1); rc=$?
took=$SECONDS
check "--seconds 0.5 stops the burial probes (exit $rc in $took s: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"time limit"* ]] && [ "$took" -lt 30 ]'

# 6b. The memory budget: counted as the pieces are made, refused with the numbers.
out=$("$facet" bake "$data/cornell/cornell.json" -o b6b --texels-per-unit 0.1 --subdivisions 8 --memory-budget-mb 16 2>&1); rc=$?
check "--memory-budget-mb 16 refuses a bake of 8 x 8 pieces a texel (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"memory_budget_bytes: the bake needs more than"*"16 MiB"* ]]'

# 7. A scene whose own texture is named lightmap_0: the lightmap takes another name.
mkdir -p named && cp model/sub/t.png named/t.png
cat > named/scene.json <<'EOF'
{"camera": {"eye": [0, 3, 3], "target": [0, 0, 0]},
 "textures": [{"name": "lightmap_0", "file": "t.png"}],
 "materials": [{"name": "m", "diffuse": [0.8, 0.8, 0.8], "diffuse_texture": "lightmap_0"}],
 "meshes": [{"name": "q", "shape": "plane"}],
 "objects": [{"mesh": "q", "material": "m"}],
 "lights": [{"type": "directional", "direction": [0, -1, 0]}]}
EOF
out=$("$facet" bake named/scene.json -o b7 "${quick[@]}" 2>&1); rc=$?
check "a scene texture named lightmap_0 bakes (exit $rc: $out)" '[ $rc -eq 0 ]'
check "  and its lightmap is another texture, the bake's file" "python3 -c '
import json, sys
d = json.load(open(\"b7/scene.json\"))
lm = d[\"objects\"][0][\"lightmap\"][\"texture\"]
t = {x[\"name\"]: x[\"file\"] for x in d[\"textures\"]}
sys.exit(0 if lm != \"lightmap_0\" and t[lm] == \"lightmap_0.png\" and t[\"lightmap_0\"] == \"scene_files/0_t.png\" else 1)'"
out=$("$facet" render b7/scene.json -o b7.png --width 16 --height 16 2>&1); rc=$?
check "  and renders (exit $rc: $out)" '[ $rc -eq 0 ]'

exit $failed
