#!/bin/sh
# sscape measure of a body given by sliders, by a fit's parameters, or as a mesh: a body sscape synth
# wrote (in any units), a registration brought to rest by its report, a posed mesh said to be far;
# and the refusals.
# usage: cli_measure_inputs.sh SSCAPE OUT_DIR SIM_PREFIX (cli_simulate's scan, fitted and registered)
set -u
sscape=$1 out=$2/measure_inputs sim=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
value() { awk -v m="$1" '$1 == m {print $2}' "$2"; }  # value NAME TABLE
same() {  # same TABLE_A TABLE_B: every measurement printed alike to 0.02 (cm, m2, L, kg)
    for m in stature chest_girth waist_girth hip_girth thigh_girth arm_length inseam surface_area volume mass; do
        a=$(value "$m" "$1") b=$(value "$m" "$2")
        [ -n "$a" ] && [ -n "$b" ] || fail "$m missing in $1 or $2"
        awk -v a="$a" -v b="$b" 'BEGIN {d = a - b; exit !(d <= 0.02 && d >= -0.02)}' || fail "$m: $a in $1, $b in $2"
    done
}

# A mesh sscape synth wrote measures as the body it is.
"$sscape" synth --shape 1,-0.5 -o "$out/body.obj" > /dev/null || fail "synth"
"$sscape" measure --shape 1,-0.5 > "$out/shape.txt" || fail "measure --shape"
"$sscape" measure --mesh "$out/body.obj" --png "$out/mesh.png" > "$out/mesh.txt" 2>&1 || { cat "$out/mesh.txt"; fail "measure --mesh"; }
cat "$out/mesh.txt"
same "$out/shape.txt" "$out/mesh.txt"
grep -q "measured in the posture it has" "$out/mesh.txt" && grep -q "^mesh: 0.0 mm from the model's nearest body" "$out/mesh.txt" || fail "the mesh's lines"
[ -s "$out/mesh.png" ] || fail "no picture of the mesh's measurements"
# The same in millimetres, with --units; without, refused with the units that fit.
awk '$1 == "v" {printf "v %.4f %.4f %.4f\n", 1000 * $2, 1000 * $3, 1000 * $4; next} {print}' "$out/body.obj" > "$out/body_mm.obj"
"$sscape" measure --mesh "$out/body_mm.obj" --units mm > "$out/mm.txt" 2>&1 || { cat "$out/mm.txt"; fail "measure --mesh --units mm"; }
same "$out/shape.txt" "$out/mm.txt"
"$sscape" measure --mesh "$out/body_mm.obj" > "$out/bad.txt" 2>&1 && fail "millimetres read as metres"
grep -q "with --units mm it would span" "$out/bad.txt" || { cat "$out/bad.txt"; fail "the units message"; }

# Sliders from the given shape.
"$sscape" measure --sliders stature=1.85 > "$out/sliders.txt" || fail "measure --sliders"
awk -v s="$(value stature "$out/sliders.txt")" 'BEGIN {exit !(s > 184 && s < 186)}' || fail "stature slider 1.85 measured $(value stature "$out/sliders.txt") cm"
"$sscape" measure --sliders height=1.85 > "$out/bad.txt" 2>&1; code=$?
[ "$code" -eq 2 ] && grep -q "no slider 'height' (it has: stature" "$out/bad.txt" || { cat "$out/bad.txt"; fail "an unknown slider exited $code"; }

# A fit's parameters: the shape it found, at rest.
"$sscape" measure --params "$sim"_fit.json --json > "$out/params.json" || fail "measure --params"
shape=$(/usr/bin/python3 -c 'import json, sys; print(",".join(repr(v) for v in json.load(open(sys.argv[1]))["shape"]))' "$sim"_fit.json) || fail "the fit's shape"
"$sscape" measure --shape "$shape" > "$out/fit_shape.txt" || fail "measure --shape of the fit"
"$sscape" measure --params "$sim"_fit.json > "$out/params.txt" || fail "measure --params table"
same "$out/fit_shape.txt" "$out/params.txt"
echo '{"shape": [1, 2], "frames": []}' > "$out/not_a_fit.json"
"$sscape" measure --params "$out/not_a_fit.json" > "$out/bad.txt" 2>&1 && fail "a broken params file accepted"
grep -q "not_a_fit.json: .*expected sscape fit --params output" "$out/bad.txt" || { cat "$out/bad.txt"; fail "the params message"; }
# Values no fit gives, in an otherwise good file: refused by measure and synth, naming the value
# (a shape of 1e300 once failed late, 30 SD made a body, a rotation of length 2 was used).
edit() {  # edit NAME PYTHON_STATEMENT_ON_j
    /usr/bin/python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); exec(sys.argv[3]); json.dump(j, open(sys.argv[2], "w"))' \
        "$sim"_fit.json "$out/$1.json" "$2" || fail "editing $1"
}
edit huge 'j["shape"][0] = 1e300'
edit far_out 'j["shape"][1] = 30'
edit long_rotation 'r = j["frames"][0]["rotations_xyzw"]; k = next(iter(r)); r[k] = [0.9, 0.9, 0.9, 0.9]'
edit too_many 'j["shape"] = j["shape"] + [0.0] * 400'
for f in huge:"shape\[0\] is 1e+300, outside" far_out:"shape\[1\] is 30, outside" long_rotation:"is not a unit quaternion (length 1.8" too_many:"shape needs at most"; do
    name=${f%%:*} message=${f#*:}
    "$sscape" measure --params "$out/$name.json" > "$out/bad.txt" 2>&1 && fail "measure took $name"
    grep -q "$name.json: .*$message" "$out/bad.txt" || { cat "$out/bad.txt"; fail "measure's message for $name"; }
    "$sscape" synth --params "$out/$name.json" -o "$out/$name.obj" > "$out/bad.txt" 2>&1 && fail "synth took $name"
    grep -q "$name.json: .*$message" "$out/bad.txt" || { cat "$out/bad.txt"; fail "synth's message for $name"; }
    [ -e "$out/$name.obj" ] && fail "synth wrote a body from $name"
done

# A registration: brought to rest with its report's model fit, near the shape space; the posed truth
# as it stands, said to be far.
"$sscape" measure --mesh "$sim"_registered.ply > "$out/registered.txt" 2>&1 || { cat "$out/registered.txt"; fail "measure a registration"; }
grep -q "brought to rest with its registration's model fit" "$out/registered.txt" || { cat "$out/registered.txt"; fail "not brought to rest"; }
grep -q "far:" "$out/registered.txt" && { cat "$out/registered.txt"; fail "the registration at rest said to be far"; }
"$sscape" measure --mesh "$sim"_truth.obj > "$out/posed.txt" 2>&1 || { cat "$out/posed.txt"; fail "measure the posed truth"; }
grep -q "far: a posed body" "$out/posed.txt" || { cat "$out/posed.txt"; fail "the posed mesh not said to be far"; }
"$sscape" measure --mesh "$sim"_registered.ply --units mm > "$out/bad.txt" 2>&1 && fail "--units beside a registration's report"
"$sscape" measure --mesh "$sim"_scan.ply > "$out/bad.txt" 2>&1 && fail "a scan measured as a mesh"
grep -q "vertices; the model has" "$out/bad.txt" || { cat "$out/bad.txt"; fail "the vertex count message"; }
"$sscape" measure --units mm > "$out/bad.txt" 2>&1; [ $? -eq 2 ] || fail "--units without --mesh"
# A registration's report holds its model fit in the same format as fit --params: synth makes that
# body from it, the segments' coefficients included (without them, another body).
"$sscape" synth --params "$sim"_registered.json -o "$out/from_report.obj" > /dev/null || fail "synth --params a registration's report"
/usr/bin/python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); assert j["fit"]["format"] == "sscape fit parameters 2" and j["fit"]["segment_shape"]; del j["fit"]["segment_shape"]; json.dump(j, open(sys.argv[2], "w"))' \
    "$sim"_registered.json "$out/whole_only.json" || fail "the report's fit has no segment coefficients"
"$sscape" synth --params "$out/whole_only.json" -o "$out/whole_only.obj" > /dev/null || fail "synth --params without segments"
cmp -s "$out/from_report.obj" "$out/whole_only.obj" && fail "the fit's segment coefficients were not applied"
echo "measure: sliders, a fit's parameters and meshes measured; refusals clear"
