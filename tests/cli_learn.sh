#!/bin/sh
# `sscape learn` from a fresh set of registrations: simulate scans, register each (mesh and report
# beside it), learn a model with given attributes, read it back; and the refusals, which write
# nothing.
# usage: cli_learn.sh SSCAPE OUT_DIR [small]
#   small (the sanitizer build): 4 scans instead of 5 (the fewest that 3 components need).
set -u
sscape=$1 out=$2/learn scans="1 2 3 4 5"
[ "${3:-full}" = small ] && scans="1 2 3 4"
count=$(echo $scans | wc -w)
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
echo "scan,age,weight_kg" > "$out/attributes.csv"
for i in $scans; do
    "$sscape" simulate -o "$out/s$i" --seed "$i" --points 8000 --pose-amount 0.4 > /dev/null || fail "simulate $i"
    "$sscape" register "$out/s${i}_scan.ply" -o "$out/reg$i.ply" --report "$out/reg$i.json" > "$out/register$i.txt" 2>&1 ||
        { cat "$out/register$i.txt"; fail "register $i"; }
    echo "reg$i,$((20 + 7 * i)),$((55 + 4 * i))" >> "$out/attributes.csv"
done
"$sscape" learn "$out"/reg?.ply --components 3 --attributes "$out/attributes.csv" --license "CC-BY-4.0 (test scans)" -o "$out/learned.sscape" > "$out/learn.txt" 2>&1 ||
    { cat "$out/learn.txt"; fail "learn"; }
cat "$out/learn.txt"
grep -q "3 components from $count registrations (posture normalization skeleton)" "$out/learn.txt" || fail "learn's summary"
grep -q "attributes: [0-9]* measured, 2 given" "$out/learn.txt" || fail "the given attributes"
"$sscape" info "$out/learned.sscape" > "$out/info.txt" 2>&1 || { cat "$out/info.txt"; fail "info on the learned model"; }
grep -q "3 shape components\|components: 3\|3 components" "$out/info.txt" || { cat "$out/info.txt"; fail "info's component count"; }
grep -qi "age" "$out/info.txt" || { cat "$out/info.txt"; fail "info lists the given attribute"; }
grep -q "CC-BY-4.0 (test scans)" "$out/info.txt" || { cat "$out/info.txt"; fail "the given licence"; }
"$sscape" synth "$out/learned.sscape" --random 1 -o "$out/body.obj" > /dev/null 2>&1 || fail "a body of the learned model"
# A fit's parameters carry its model's digest: read with another model they are refused (once they
# made another body, 31 mm RMS away, and exit 0).
"$sscape" fit "$out/learned.sscape" --landmarks "$out/s1.lnd" -o "$out/fit1.obj" --params "$out/fit1.json" > /dev/null 2>&1 || fail "fit with the learned model"
grep -q '"model_digest"' "$out/fit1.json" || fail "the parameters name no model digest"
"$sscape" synth "$out/learned.sscape" --params "$out/fit1.json" -o "$out/fit1_again.obj" > /dev/null 2>&1 || fail "synth --params with its model"
"$sscape" synth --params "$out/fit1.json" -o "$out/fit1_other.obj" > "$out/other_model.txt" 2>&1
[ $? -eq 1 ] && grep -q "was fitted with the model 'sscape-learned' (digest [0-9a-f]*), not this one" "$out/other_model.txt" && [ ! -e "$out/fit1_other.obj" ] ||
    { cat "$out/other_model.txt"; fail "synth --params with another model"; }
"$sscape" learn "$out"/reg?.ply --posture none --components 2 -o "$out/none.sscape" > /dev/null 2>&1 || fail "posture none"
# The laplacian method needs no model fits (registrations started rigidly have none): the
# reports' fits taken out, skeleton refuses and laplacian learns.
mkdir -p "$out/bare" && cp "$out"/reg?.ply "$out/bare/"
for i in $scans; do
    /usr/bin/python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); r.pop("fit"); json.dump(r, open(sys.argv[2], "w"))' \
        "$out/reg$i.json" "$out/bare/reg$i.json" || fail "a report without its fit"
done
"$sscape" learn "$out"/bare/reg?.ply --components 2 -o "$out/bad.sscape" > "$out/nofit.txt" 2>&1
[ $? -ne 0 ] && grep -q "has no model fit.*--posture none or laplacian" "$out/nofit.txt" && [ ! -e "$out/bad.sscape" ] ||
    { cat "$out/nofit.txt"; fail "skeleton without fits"; }
"$sscape" learn "$out"/bare/reg?.ply --posture laplacian --components 2 -o "$out/laplacian.sscape" > "$out/laplacian.txt" 2>&1 ||
    { cat "$out/laplacian.txt"; fail "posture laplacian"; }
grep -q "(posture normalization laplacian)" "$out/laplacian.txt" || { cat "$out/laplacian.txt"; fail "learn's summary names laplacian"; }
"$sscape" synth "$out/laplacian.sscape" --random 1 -o "$out/laplacian_body.obj" > /dev/null 2>&1 || fail "a body of the laplacian model"

# Segment shape spaces: learned, listed by info, set per segment by synth.
"$sscape" learn "$out"/reg?.ply --components 3 --segment-components 2 -o "$out/segments.sscape" > "$out/segments.txt" 2>&1 ||
    { cat "$out/segments.txt"; fail "learn with segments"; }
grep -q "segment compactness" "$out/segments.txt" || { cat "$out/segments.txt"; fail "learn reports the segments' compactness"; }
"$sscape" info "$out/segments.sscape" > "$out/info_segments.txt" 2>&1 || fail "info on the model with segments"
grep -q "arm_l  *2 components" "$out/info_segments.txt" || { cat "$out/info_segments.txt"; fail "info lists the segments"; }
"$sscape" info "$out/segments.sscape" --segments-png "$out/segments.png" > /dev/null 2>&1 || fail "info --segments-png"
[ "$(head -c 4 "$out/segments.png" | od -An -c | tr -d ' ')" = "211PNG" ] || fail "the segments picture is not a PNG"
"$sscape" info "$out/body.obj" --segments-png "$out/x.png" > /dev/null 2>&1 && fail "info --segments-png on a mesh"
"$sscape" info "$out/learned.sscape" --segments-png "$out/none.png" > "$out/none.txt" 2>&1
[ $? -eq 2 ] && grep -q "no segment shape spaces" "$out/none.txt" && [ ! -e "$out/none.png" ] || { cat "$out/none.txt"; fail "info --segments-png on a model without segments"; }
"$sscape" synth "$out/segments.sscape" --segment arm_l=1.5,-0.3 --segment head=1 -o "$out/segment_body.obj" > /dev/null 2>&1 || fail "synth --segment"
cmp -s "$out/segment_body.obj" "$out/body.obj" && fail "synth --segment changed nothing"
"$sscape" synth "$out/segments.sscape" --segment tail=1 -o "$out/no.obj" > "$out/no.txt" 2>&1
[ $? -eq 2 ] && grep -q "its segments: head, arm_l" "$out/no.txt" && [ ! -e "$out/no.obj" ] || { cat "$out/no.txt"; fail "synth --segment with an unknown name"; }
"$sscape" synth "$out/segments.sscape" --segment arm_l=1,2,3 -o "$out/no.obj" > "$out/no.txt" 2>&1
[ $? -ne 0 ] && grep -q "segment 'arm_l' has 2 components" "$out/no.txt" && [ ! -e "$out/no.obj" ] || { cat "$out/no.txt"; fail "synth --segment with too many values"; }

# Evaluation against the training-set size: refusals before any work.
"$sscape" evaluate "$out"/reg?.ply --training-sizes 2 -o "$out/sizes" > "$out/sizes.txt" 2>&1
[ $? -eq 2 ] && grep -q "'2' is not a number of registrations" "$out/sizes.txt" || { cat "$out/sizes.txt"; fail "evaluate --training-sizes 2"; }
"$sscape" evaluate "$out"/reg?.ply --training-sizes all -o "$out/sizes" > "$out/sizes.txt" 2>&1
[ $? -eq 1 ] && grep -q "needs at least 10" "$out/sizes.txt" && [ ! -e "$out/sizes.csv" ] || { cat "$out/sizes.txt"; fail "evaluate --training-sizes with 5 registrations"; }

# Refusals: a message, a non-zero exit, no file.
expect() {  # expect CODE PATTERN ARGS...
    code=$1 pattern=$2; shift 2
    rm -f "$out/bad.sscape"
    "$sscape" learn "$@" -o "$out/bad.sscape" > "$out/bad.txt" 2>&1
    got=$?
    if [ "$got" -ne "$code" ] || ! grep -q -e "$pattern" "$out/bad.txt"; then cat "$out/bad.txt"; fail "learn $* exited $got (expected $code) or lacks '$pattern'"; fi
    [ ! -e "$out/bad.sscape" ] || fail "learn $* wrote a model"
}
expect 2 "needs more than that many registrations" "$out"/reg?.ply --components 5
expect 1 "components per segment" "$out"/reg?.ply --components 2 --segment-components 5
cp "$out/reg1.ply" "$out/lonely.ply"
expect 1 "no registration report" "$out/reg1.ply" "$out/reg2.ply" "$out/lonely.ply" --components 2
echo "scan,age" > "$out/short.csv" && echo "reg1,30" >> "$out/short.csv"
expect 1 "no row for reg2" "$out"/reg?.ply --components 2 --attributes "$out/short.csv"
printf 'scan,age\nreg1,abc\n' > "$out/text.csv"
expect 1 "'abc' is not a finite number" "$out"/reg?.ply --components 2 --attributes "$out/text.csv"
echo '{"scan": "x"' > "$out/broken.json" && cp "$out/reg1.ply" "$out/broken.ply"
expect 1 "not a registration report" "$out/reg1.ply" "$out/reg2.ply" "$out/broken.ply" --components 2
"$sscape" synth --random 1 -o "$out/other.obj" > /dev/null 2>&1
sed -n '1,/^f /p' "$out/other.obj" | grep '^v ' | head -100 > "$out/few.obj"
cp "$out/reg1.json" "$out/few.json"
expect 1 "100 vertices; the model has" "$out/reg1.ply" "$out/reg2.ply" "$out/few.obj" --components 2
# Degenerate inputs say what is wrong with them (issue 47, items 5 and 14): once a constant column or
# identical registrations failed on "attributes.covariance has a diagonal entry <= 0", evaluate
# left a CSV of -nan, and 3000 columns ran past 170 s.
echo "scan,age,height" > "$out/constant.csv"
for i in $scans; do echo "reg$i,30,$((150 + i))" >> "$out/constant.csv"; done
expect 1 "attribute age is 30 for every registration" "$out"/reg?.ply --components 2 --attributes "$out/constant.csv"
/usr/bin/python3 -c 'import sys
print("scan," + ",".join("a%d" % c for c in range(65)))
for r in sys.argv[1:]: print(r + "," + ",".join(str(int(r[3:]) * 7 + c % 5) for c in range(65)))' $(for i in $scans; do echo reg$i; done) > "$out/wide.csv"
expect 1 "65 attributes; at most 64" "$out"/reg?.ply --components 2 --attributes "$out/wide.csv"
for i in 1 2 3; do cp "$out/reg1.ply" "$out/same$i.ply" && cp "$out/reg1.json" "$out/same$i.json"; done
expect 1 "the 3 registrations are all the same body" "$out"/same?.ply --components 2
"$sscape" evaluate "$out"/same?.ply -o "$out/same_eval" > "$out/same_eval.txt" 2>&1
[ $? -eq 1 ] && grep -q "all the same body" "$out/same_eval.txt" && [ ! -e "$out/same_eval.csv" ] && [ ! -e "$out/same_eval_compactness.png" ] ||
    { cat "$out/same_eval.txt"; ls "$out"; fail "evaluate on identical registrations"; }
# evaluate --models with a model of another mesh of as many vertices: refused (once it ran and
# reported errors near 600 mm).
"$sscape" make-test-model -o "$out/other_mesh.sscape" --vertices 13380 --components 3 > /dev/null || fail "make-test-model"
"$sscape" evaluate "$out"/reg?.ply --models "$out/other_mesh.sscape" -o "$out/other_eval" > "$out/other_eval.txt" 2>&1
[ $? -eq 1 ] && grep -q "its mesh is not the one the registrations were made in" "$out/other_eval.txt" && [ ! -e "$out/other_eval.csv" ] ||
    { cat "$out/other_eval.txt"; fail "evaluate --models with another mesh"; }
echo "learn: model written and read back; refusals clear"
