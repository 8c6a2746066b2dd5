#!/usr/bin/env bash
# Every `facet render` option that names a change of the picture changes it, and every option
# that must not (threads, tile size, instruction set) leaves the bytes as they were: an option
# read and then ignored fails here. The built-in scene (and a scene with shadows), 96 x 54.
#   usage: cli_options_test.sh FACET DATA_DIR WORKDIR
set -u
facet="$1" data="$2" work="$3"
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
failed=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAILED: $1"; failed=1; fi; }
size=(--width 96 --height 54)

"$facet" render -o base.png "${size[@]}" >/dev/null 2>&1 || { echo "FAILED: the base render"; exit 1; }
n=0
while read -r options; do
  [ -z "$options" ] && continue
  n=$((n + 1))
  out=$("$facet" render -o "changed_$n.png" "${size[@]}" $options 2>&1); rc=$?
  check "$options changes the picture (exit $rc)" '[ $rc -eq 0 ] && ! cmp -s base.png "changed_$n.png"'
done <<'EOF'
--shading flat
--shading phong
--cull front
--cull none
--msaa 4
--linear
--exposure 1
--tone-mapping aces
--clear 0.5,0.25,0,1
--view 90,20
--fov 70
EOF
# A turntable's frames are numbered files: frame 1 of 2 is turned by half of --orbit, frame 0 not.
out=$("$facet" render -o turn.png "${size[@]}" --frames 2 --orbit 90 2>&1); rc=$?
check "--frames 2: frame 1 is turned from frame 0 (exit $rc)" '[ $rc -eq 0 ] && [ -s turn_0000.png ] && [ -s turn_0001.png ] && ! cmp -s turn_0000.png turn_0001.png'
"$facet" render -o turn180.png "${size[@]}" --frames 2 --orbit 180 >/dev/null 2>&1
check "--orbit changes how far frame 1 turns" '[ -s turn180_0001.png ] && ! cmp -s turn_0001.png turn180_0001.png'

while read -r options; do
  [ -z "$options" ] && continue
  n=$((n + 1))
  out=$("$facet" render -o "same_$n.png" "${size[@]}" $options 2>&1); rc=$?
  check "$options keeps the bytes (exit $rc)" '[ $rc -eq 0 ] && cmp -s base.png "same_$n.png"'
done <<EOF
--threads 1
--tile 8
--tile 256
--srgb
--exposure 0
--tone-mapping none
--pixel-precision exact
--seconds 0.05
EOF

# Another instruction set: the lighting kernels round differently in float (within their stated
# contract), which sRGB encoding can turn into a step somewhere; never more.
out=$("$facet" render -o isa.png "${size[@]}" --isa sse2 2>&1); rc=$?
check "--isa sse2 keeps the picture within a step (exit $rc)" '[ $rc -eq 0 ] && "$facet" compare --tolerance 1 base.png isa.png >/dev/null'
# --exposure auto meters the built-in scene (GL's by default) and --exposure takes only stops or auto.
out=$("$facet" render -o auto.png "${size[@]}" --exposure auto --stats 2>&1); rc=$?
check "--exposure auto reports the metered exposure (exit $rc)" '[ $rc -eq 0 ] && echo "$out" | grep -Eq "exposure [-+][0-9.]+ EV \(metered\)"'
out=$("$facet" render -o bad.png "${size[@]}" --exposure bright 2>&1); rc=$?
check "--exposure bright is refused (exit $rc)" '[ $rc -eq 2 ] && echo "$out" | grep -q "expected stops"'

# Shadows: --shadows none and each method change a shadowed scene; the method is honoured.
shadows="$data/scenes/shadows.json"
"$facet" render "$shadows" -o s_none.png "${size[@]}" --shading phong --shadows none >/dev/null 2>&1
for method in raycast map volume; do
  out=$("$facet" render "$shadows" -o "s_$method.png" "${size[@]}" --shading phong --shadows "$method" 2>&1); rc=$?
  check "--shadows $method casts shadows (exit $rc)" '[ $rc -eq 0 ] && ! cmp -s s_none.png "s_$method.png"'
done
check "map and ray-cast shadows are not the same method" '! cmp -s s_map.png s_raycast.png'

# --hdr keeps light above 1 in float output; --transparent-order reorders blended objects.
"$facet" render -o plain.pfm "${size[@]}" >/dev/null 2>&1
"$facet" render -o hdr.pfm "${size[@]}" --hdr >/dev/null 2>&1
check "--hdr changes the float output" '! cmp -s plain.pfm hdr.pfm'
# Two half-transparent planes, the near one submitted first.
cat > blended.json <<'SCENE'
{"camera": {"eye": [0, 0, 4], "target": [0, 0, 0]},
 "materials": [{"name": "red", "emissive": [1, 0, 0], "diffuse": 0, "ambient": 0, "alpha": 0.5, "blend": "alpha"},
               {"name": "green", "emissive": [0, 1, 0], "diffuse": 0, "ambient": 0, "alpha": 0.5, "blend": "alpha"}],
 "meshes": [{"name": "quad", "shape": "plane", "size_x": 2, "size_z": 2}],
 "objects": [{"mesh": "quad", "material": "red", "translate": [0, 0, 1], "rotate_deg": [90, 0, 0]},
             {"mesh": "quad", "material": "green", "translate": [0, 0, 0], "rotate_deg": [90, 0, 0]}]}
SCENE
"$facet" render blended.json -o t_sub.png "${size[@]}" --cull none --transparent-order submission >/dev/null 2>&1
"$facet" render blended.json -o t_b2f.png "${size[@]}" --cull none --transparent-order back_to_front >/dev/null 2>&1
check "--transparent-order changes a scene of blended objects" '[ -s t_sub.png ] && ! cmp -s t_sub.png t_b2f.png'
exit $failed
