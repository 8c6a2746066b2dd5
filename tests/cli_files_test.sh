#!/usr/bin/env bash
# facet's command line and files: a FIFO is refused at once (never blocks), -o into a missing
# directory fails without creating it, and a write cut short by `ulimit -f` keeps the old file
# byte for byte and leaves no temporary file; check and render report ray-cast shadows, shadow maps and volumes.   usage: cli_files_test.sh FACET GOLDEN.png WORKDIR
set -u
facet="$1" golden="$2" work="$3"
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
failed=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAILED: $1"; failed=1; fi; }

mkfifo pipe.png
out=$(timeout 20 "$facet" compare pipe.png "$golden" 2>&1); rc=$?
check "compare refuses a FIFO (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"not a regular file"* ]]'
out=$(timeout 20 "$facet" render pipe.png -o x.png --width 8 --height 8 2>&1); rc=$?
check "render refuses a FIFO scene (exit $rc)" '[ $rc -eq 2 ] && [[ "$out" == *"not a regular file"* ]]'

out=$("$facet" render -o missing/dir/x.png --width 8 --height 8 2>&1); rc=$?
check "-o into a missing directory fails (exit $rc: $out)" '[ $rc -eq 2 ] && [ ! -e missing ]'

for ext in png pfm exr; do
  printf 'the old output' > old.$ext
  out=$(bash -c "ulimit -f 16; exec \"$facet\" render -o old.$ext --width 640 --height 480" 2>&1); rc=$?
  check "a write past ulimit -f fails (.$ext, exit $rc: $out)" '[ $rc -eq 2 ]'
  check "the old .$ext file is intact" '[ "$(cat old.$ext)" = "the old output" ]'
  check "no temporary file is left (.$ext)" '[ "$(ls | grep -c "^old\.$ext\.")" -eq 0 ]'
done

# Outputs that exist and are not regular files are refused at once, never replaced or blocked on;
# a link to a regular file is replaced by the new file (the file it led to is left as it was).
for ext in png pfm exr; do
  mkfifo "fifo.$ext"
  out=$(timeout 20 "$facet" render -o "fifo.$ext" --width 8 --height 8 2>&1); rc=$?
  check "-o a FIFO .$ext is refused (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"not a regular file"* ]] && [ -p "fifo.$ext" ]'
  mkdir "dir.$ext"
  out=$("$facet" render -o "dir.$ext" --width 8 --height 8 2>&1); rc=$?
  check "-o a folder .$ext is refused (exit $rc: $out)" '[ $rc -eq 2 ] && [ -d "dir.$ext" ]'
  printf 'the target' > "target.$ext"
  ln -s "target.$ext" "link.$ext"
  out=$("$facet" render -o "link.$ext" --width 8 --height 8 2>&1); rc=$?
  check "-o a link .$ext replaces the link, not its target (exit $rc: $out)" '[ $rc -eq 0 ] && [ ! -L "link.$ext" ] && [ -s "link.$ext" ] && [ "$(cat target.$ext)" = "the target" ]'
done
if mknod null.png c 1 3 2>/dev/null; then  # as root: a character device named like the output
  out=$("$facet" render -o null.png --width 8 --height 8 2>&1); rc=$?
  check "-o a device is refused and stays a device (exit $rc: $out)" '[ $rc -eq 2 ] && [ -c null.png ]'
fi

# --time-limit: a frame of 2 x 10^4 lights a pixel (minutes) stops at the limit, in under 30 s;
# so does a load that takes longer than the limit.
python3 -c "
import json
lights = [{'type': 'point', 'position': [i % 7 - 3, 2, i % 5 - 2], 'diffuse': [1e-5, 1e-5, 1e-5]} for i in range(4000)]
json.dump({'meshes': [{'name': 's', 'shape': 'sphere'}], 'materials': [{'name': 'm'}],
           'objects': [{'mesh': 's', 'material': 'm'}], 'lights': lights,
           'camera': {'eye': [0, 0, 1.3], 'target': [0, 0, 0]}}, open('many_lights.json', 'w'))
"
SECONDS=0
# 4,000 lights on a sphere that fills the view: a Phong frame of 1024 x 1024 took 4 s on 2 cores (release), this one has four times its pixels, and
# the file loads well within the limit also under AddressSanitizer on a loaded machine (20,000
# lights took the load past 1.5 s there).
out=$("$facet" render many_lights.json -o slow.png --width 2048 --height 2048 --shading phong --no-light-culling --time-limit 3 2>&1); rc=$?
took=$SECONDS
check "--time-limit 3 stops a frame of minutes (exit $rc in $took s: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"render: stopped at the time limit"* ]] && [ "$took" -lt 30 ] && [ ! -e slow.png ]'
out=$("$facet" render many_lights.json -o slow.png --width 8 --height 8 --time-limit 0.001 2>&1); rc=$?
check "--time-limit stops a load too (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"many_lights.json: stopped at the time limit"* ]]'

# --depth-mode: gl and reversed store depth differently (the depth written differs in its bits).
"$facet" render -o gl.png --width 64 --height 36 --depth gl.pfm --depth-mode gl >/dev/null 2>&1
"$facet" render -o rev.png --width 64 --height 36 --depth rev.pfm --depth-mode reversed >/dev/null 2>&1
check "--depth-mode reversed changes the stored depth" '[ -s gl.pfm ] && [ -s rev.pfm ] && ! cmp -s gl.pfm rev.pfm'

# Shadows: facet check and facet render know where they are drawn.
shadows="$(cd "$(dirname "$golden")/../scenes" && pwd)/shadows.json"
out=$("$facet" check "$shadows" --shading phong 2>&1); rc=$?
check "check reports the shadowed lights (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" == *"shadows: 2 lights (sun raycast, spot raycast)"* ]]'
out=$("$facet" render "$shadows" --width 64 --height 48 -o gouraud.png 2>&1); rc=$?
check "render draws shadows in Gouraud shading too (exit $rc: $out)" '[ $rc -eq 0 ] && [ -s gouraud.png ]'
out=$("$facet" render "$shadows" --shading phong --width 64 --height 48 --stats -o shadows.png 2>&1); rc=$?
check "render draws ray-cast shadows (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" == *"shadows     4108 caster triangles"* ]] && [ -s shadows.png ]'
out=$("$facet" check "$shadows" --shading phong --shadows map 2>&1); rc=$?
check "check --shadows map turns every light's shadows into maps (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" == *"sun map 2048^2 pcf3x3, spot map 2048^2 pcf3x3"* ]]'
out=$("$facet" check "$shadows" --shading phong --shadows volume 2>&1); rc=$?
check "check --shadows volume says which caster meshes are closed (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" == *"sun volume (stencil), spot volume (stencil)"* ]] && [[ "$out" == *"volumes: exact, hard"*"2 closed caster meshes, 1 open (ground)"* ]]'
out=$("$facet" render "$shadows" --shading phong --shadows volume --width 64 --height 48 --stats -o volumes.png 2>&1); rc=$?
check "render draws shadow volumes (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" == *"shadows     4108 caster triangles"* ]] && [ -s volumes.png ]'
out=$("$facet" render "$shadows" --shading phong --shadows none --width 16 --height 16 -o none.png 2>&1); rc=$?
check "render --shadows none draws no shadows (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" != *"shadows"* ]]'
out=$("$facet" check "$shadows" --shading phong --shadows stencil 2>&1); rc=$?
check "--shadows names an unknown method (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"--shadows: unknown method"*"stencil"* ]]'
maps="$(dirname "$shadows")/shadow_maps.json"
out=$("$facet" check "$maps" --shading phong 2>&1); rc=$?
check "check reports the shadow maps (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" == *"sun map 2048^2 pcf3x3, spot map 1024^2 pcf5x5, lamp map 2048^2 pcf2x2 cube"* ]]'
out=$("$facet" render "$maps" --shading phong --width 64 --height 48 --stats -o maps.png 2>&1); rc=$?
check "render draws shadow maps (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" == *"maps: 30.41 M texels"* ]] && [ -s maps.png ]'
# Models: glTF and OBJ + MTL without a scene file, framing, the default rig, turntables, errors.
corpus="$(cd "$(dirname "$golden")/../../../tools/fuzz/corpus/gltf" && pwd)"
out=$("$facet" render "$corpus/colours.gltf" --width 64 --height 48 -o colours.png 2>&1); rc=$?
check "render frames and lights a glTF without camera or lights (exit $rc: $out)" '[ $rc -eq 0 ] && [ -s colours.png ] && [[ "$out" == *"no camera in the file: framing"* ]] && [[ "$out" == *"neutral studio"* ]]'
out=$("$facet" render "$corpus/colours.gltf" --gl-materials --width 64 --height 48 -o colours_gl.png 2>&1); rc=$?
check "--gl-materials: GL's model and facet's rig for a glTF without lights (exit $rc: $out)" '[ $rc -eq 0 ] && [ -s colours_gl.png ] && [[ "$out" == *"default rig"* ]] && ! cmp -s colours.png colours_gl.png'
out=$("$facet" render "$corpus/textured_lit.glb" --width 64 --height 48 -o glb.png 2>&1); rc=$?
check "render uses a .glb's camera and lights, and lists its warnings (exit $rc: $out)" '[ $rc -eq 0 ] && [ -s glb.png ] && [[ "$out" != *"framing"* ]] && [[ "$out" == *"warning: samplers[0]"* ]]'
printf 'newmtl red\nKd 1 0 0\nmap_Kd red.png\n' > m.mtl
printf 'mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl red\nf 1/1 2/1 3/1\n' > m.obj
out=$("$facet" render m.obj --strict --width 64 --height 48 -o m.png 2>&1); rc=$?
check "--strict: a missing texture of an MTL is an error naming file and line (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"m.mtl:3"* ]] && [[ "$out" == *"red.png"* ]] && [ ! -e m.png ]'
out=$("$facet" render m.obj --allow-missing --width 64 --height 48 -o m.png 2>&1); rc=$?
check "--allow-missing (the default) draws it untextured with a warning (exit $rc: $out)" '[ $rc -eq 0 ] && [ -s m.png ] && [[ "$out" == *"warning:"*"red.png"* ]]'
out=$("$facet" render m.obj --width 64 --height 48 -o m2.png 2>&1); rc=$?
check "by default a missing texture is a warning (exit $rc: $out)" '[ $rc -eq 0 ] && [ -s m2.png ] && [[ "$out" == *"warning:"*"red.png"* ]]'
out=$("$facet" check m.obj --strict 2>&1); rc=$?
check "check --strict refuses it (exit $rc)" '[ $rc -eq 2 ] && [[ "$out" == *"--strict"* ]]'
out=$("$facet" check m.obj --allow-missing 2>&1); rc=$?
check "check reads models (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" == *"m.obj: ok"* ]] && [[ "$out" == *"default rig"* ]]'
out=$("$facet" render m.obj --allow-missing --frames 3 --orbit 90 --width 32 --height 24 -o turn.png 2>&1); rc=$?
check "a turntable writes numbered frames and a summary (exit $rc: $out)" '[ $rc -eq 0 ] && [ -s turn_0000.png ] && [ -s turn_0002.png ] && [ ! -e turn_0003.png ] && [[ "$out" == *"3 frames in"* ]]'
printf '{"camera": {"eye": [0, 0, 5], "target": [0, 0, 10]}, "meshes": [{"name": "b", "shape": "cube"}], "objects": [{"mesh": "b"}]}' > away.json
out=$("$facet" render away.json --width 32 --height 24 -o away.png 2>&1); rc=$?
check "a frame that draws nothing says why, writes the image and exits 1 (exit $rc: $out)" '[ $rc -eq 1 ] && [ -s away.png ] && [[ "$out" == *"nothing to see (exit status 1; the image is written): every triangle is outside the view"* ]]'
out=$("$facet" check away.json 2>&1); rc=$?
check "check gives render's verdict and status (exit $rc: $out)" '[ $rc -eq 1 ] && [[ "$out" == *"nothing to see: every triangle is outside the view"* ]]'
# Fully transparent materials fill pixels that show nothing: the same verdict from both commands.
printf '{"materials": [{"name": "glass", "alpha": 0, "blend": "alpha"}], "meshes": [{"name": "b", "shape": "cube"}], "objects": [{"mesh": "b", "material": "glass"}]}' > clear.json
out=$("$facet" render clear.json --width 32 --height 24 -o clear.png --json 2>&1); rc=$?
check "an invisible model: render exits 1 naming transparency (exit $rc: $out)" '[ $rc -eq 1 ] && [[ "$out" == *"every pixel is still the background colour"* ]] && [[ "$out" == *"\"nothing_drawn\": \""*"fully transparent"* ]]'
out=$("$facet" check clear.json 2>&1); rc=$?
check "an invisible model: check agrees (exit $rc: $out)" '[ $rc -eq 1 ] && [[ "$out" == *"every pixel is still the background colour"* ]]'
out=$("$facet" render clear.json --width 32 --height 24 -o clear.png --clear 0.2,0.3,0.4 --msaa 4 2>&1); rc=$?
check "the background is found for any clear colour and sample count (exit $rc: $out)" '[ $rc -eq 1 ] && [[ "$out" == *"background colour"* ]]'
# A flat plane seen exactly edge-on has no area on screen: said so, not "degenerate".
printf '{"camera": {"eye": [0, 0, 5], "target": [0, 0, 0]}, "meshes": [{"name": "p", "shape": "plane"}], "objects": [{"mesh": "p"}]}' > edge.json
out=$("$facet" render edge.json --width 32 --height 24 -o edge.png --cull none 2>&1); rc=$?
check "an edge-on plane is named as such (exit $rc: $out)" '[ $rc -eq 1 ] && [[ "$out" == *"seen edge-on"* ]]'
out=$("$facet" render -o ok.png --width 32 --height 24 2>&1); rc=$?
check "a frame that shows something exits 0 (exit $rc: $out)" '[ $rc -eq 0 ]'
out=$("$facet" render model.fbx -o x.png 2>&1); rc=$?
check "an unsupported model type is named (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *".fbx files are not supported"* ]]'

exit $failed
