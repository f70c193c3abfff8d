#!/bin/sh
# `sscape bootstrap` on a small simulated collection: one round from the built-in model, its files
# (registrations sscape learn can read, decisions, contact sheet, model), a resumed run that redoes
# nothing, a person's decision that changes the learned model, and the refusals.
# usage: cli_bootstrap.sh SSCAPE OUT_DIR [small]
#   small (the sanitizer build): without the second registration of every scan under another up axis,
#   which runs the same code as the first, without the template-only start (the posture-model test
#   registers from the template alone under the sanitizers; the Release run checks this one), and
#   without two of the resumed runs (units spelled out, attributes: reading the same records again),
#   and 4 scans instead of 6 (models of 2 components instead of 3).
set -u
# Under a long folder name, as users' paths are: no line may be cut (a fixed-width line once lost
# the "reused" this test looks for).
sscape=$1 out=$2/bootstrap/a_folder_with_a_name_as_long_as_the_paths_of_real_collections_on_real_disks_are_every_day scale=${3:-full}
rm -rf "$2/bootstrap" && mkdir -p "$out/scans" "$out/truth"
fail() { echo "FAIL: $*"; exit 1; }
ids="1 2 3 4 5 6" components=3 eval_components=1,2,3
[ "$scale" = small ] && ids="1 2 3 4" components=2 eval_components=1,2
count=$(echo $ids | wc -w)
for i in $ids; do
    "$sscape" simulate -o "$out/truth/b$i" --seed "$((40 + i))" --points 8000 --pose-amount 0.3 > /dev/null || fail "simulate $i"
    mv "$out/truth/b${i}_scan.ply" "$out/scans/b$i.ply" && mv "$out/truth/b$i.lnd" "$out/scans/b$i.lnd"
done
printf 'ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nend_header\n1\n' > "$out/scans/broken.ply"  # fails alone
"$sscape" bootstrap "$out/scans" --rounds 1 --components $components -o "$out/run" > "$out/first.txt" 2>&1 || { cat "$out/first.txt"; fail "bootstrap"; }
cat "$out/first.txt"
grep -q "round 1: $count registered, 0 reused, 1 failed" "$out/first.txt" || fail "every scan registered, the broken one failed"
grep -q "^broken,reject,\"*registration failed: " "$out/run/round_1/decisions.csv" || fail "the broken scan's reason"
for f in round_0/model.sscape round_1/model.sscape round_1/round.json round_1/decisions.csv round_1/contact_sheet_01.png model.sscape rounds.csv; do
    [ -s "$out/run/$f" ] || fail "no $f"
done
for i in $ids; do
    [ -s "$out/run/round_1/registrations/b$i.ply" ] && [ -s "$out/run/round_1/registrations/b$i.json" ] || fail "registration $i"
done
[ "$(wc -l < "$out/run/round_1/decisions.csv")" -eq $((count + 2)) ] || fail "a decision per scan"
accepted=$(grep -c ",accept," "$out/run/round_1/decisions.csv")
[ "$accepted" -ge 3 ] || fail "only $accepted of $count accepted"
# The built-in model poses the accepted scans (the posture model by default): here it is also the
# round's model, so its registration fits are kept as the posture fits.
grep -q "round 1: the accepted scans posed by '" "$out/first.txt" || fail "the posture model's line"
[ "$(ls "$out/run/posture_fits" | wc -l)" -eq "$accepted" ] || fail "a posture fit per accepted scan"
"$sscape" info "$out/run/model.sscape" > "$out/info.txt" 2>&1 || { cat "$out/info.txt"; fail "info on the learned model"; }
grep -q "bootstrap round 1;" "$out/info.txt" || { cat "$out/info.txt"; fail "the model's provenance"; }
"$sscape" synth "$out/run/model.sscape" --random 1 -o "$out/body.obj" > /dev/null 2>&1 || fail "a body of the learned model"
"$sscape" learn "$out"/run/round_1/registrations/*.ply --components 2 -o "$out/learned.sscape" > "$out/learn.txt" 2>&1 ||
    { cat "$out/learn.txt"; fail "sscape learn on bootstrap's registrations"; }

# Resumed: nothing registered or learned again.
"$sscape" bootstrap "$out/scans" --rounds 1 --components $components -o "$out/run" > "$out/again.txt" 2>&1 || { cat "$out/again.txt"; fail "resume"; }
grep -q "round 1: 0 registered, $count reused, 1 failed.*, reused$" "$out/again.txt" || { cat "$out/again.txt"; fail "the resumed run redid work"; }

# The same reading of the scans spelled out redoes nothing; another (their up axis) registers and learns again.
if [ "$scale" = full ]; then
    cp -r "$out/run" "$out/run_cm"
    "$sscape" bootstrap "$out/scans" --rounds 1 --components 3 --units m --up y -o "$out/run_cm" > "$out/same_units.txt" 2>&1 ||
        { cat "$out/same_units.txt"; fail "resume with the same units spelled out"; }
    grep -q "round 1: 0 registered, 6 reused" "$out/same_units.txt" || { cat "$out/same_units.txt"; fail "the same units redid work"; }
    "$sscape" bootstrap "$out/scans" --rounds 1 --components 3 --up z -o "$out/run_cm" > "$out/other_up.txt" 2>&1
    grep -q ", 0 reused, " "$out/other_up.txt" || { cat "$out/other_up.txt"; fail "another up axis reused registrations"; }
    grep -q "round 1: learning from" "$out/other_up.txt" || { cat "$out/other_up.txt"; fail "new registrations reused the model"; }
fi
rm -rf "$out/run_cm"

# A person rejects an accepted scan: the registrations stay, the model is learned again without it.
first=$(grep ",accept," "$out/run/round_1/decisions.csv" | head -1 | cut -d, -f1)
printf 'scan,decision,reason,by\n%s,reject,"arm looks wrong, by eye",person\nb1,accept,,auto\n' "$first" > "$out/decisions.csv"
"$sscape" bootstrap "$out/scans" --rounds 1 --components $components --decisions "$out/decisions.csv" -o "$out/run" > "$out/person.txt" 2>&1 ||
    { cat "$out/person.txt"; fail "bootstrap with decisions"; }
grep -q "round 1: 0 registered, $count reused" "$out/person.txt" || { cat "$out/person.txt"; fail "registrations reused"; }
grep -q "round 1: learning from $((accepted - 1)) registrations" "$out/person.txt" || { cat "$out/person.txt"; fail "the model learned again"; }
grep -q "^$first,reject,\"arm looks wrong, by eye\",person" "$out/run/round_1/decisions.csv" || fail "the person's decision recorded"

# Known attributes: the model is learned again with them (the registrations stay). Under the
# sanitizers cli_learn learns with given attributes.
printf 'scan,age\nb1,31\nb2,45\nb3,27\nb4,52\nb5,38\nb6,61\nbroken,40\n' > "$out/ages.csv"
if [ "$scale" = full ]; then
    "$sscape" bootstrap "$out/scans" --rounds 1 --components 3 --decisions "$out/decisions.csv" --attributes "$out/ages.csv" -o "$out/run" > "$out/ages.txt" 2>&1 ||
        { cat "$out/ages.txt"; fail "bootstrap with attributes"; }
    grep -q "round 1: 0 registered, 6 reused" "$out/ages.txt" && grep -q "round 1: learning from" "$out/ages.txt" ||
        { cat "$out/ages.txt"; fail "learned again with the attributes"; }
    "$sscape" info "$out/run/model.sscape" | grep -qi "age" || fail "the learned model has the given attribute"
fi

# Evaluation of the round's registrations: learning with the three posture normalizations, and
# the two rounds' models against them.
"$sscape" evaluate "$out"/run/round_1/registrations/*.ply --posture none,skeleton,laplacian --components $eval_components --samples 200 -o "$out/eval" > "$out/eval.txt" 2>&1 ||
    { cat "$out/eval.txt"; fail "evaluate"; }
[ "$(grep -c '^posture ' "$out/eval.csv")" -eq $((3 * components)) ] || { cat "$out/eval.csv"; fail "a row per posture and number of components"; }
for plot in compactness generalization specificity; do [ -s "$out/eval_$plot.png" ] || fail "no $plot plot"; done
"$sscape" evaluate "$out"/run/round_1/registrations/*.ply --models "$out/run/round_0/model.sscape,$out/run/round_1/model.sscape" --components 1,$components \
    --samples 200 -o "$out/rounds" > "$out/rounds.txt" 2>&1 || { cat "$out/rounds.txt"; fail "evaluate --models"; }
grep -q "^round_1/model,$components," "$out/rounds.csv" || { cat "$out/rounds.csv"; fail "the rounds' models by folder"; }
"$sscape" evaluate "$out"/run/round_1/registrations/b1.ply "$out"/run/round_1/registrations/b2.ply -o "$out/few" > "$out/few.txt" 2>&1
[ $? -eq 2 ] && grep -q "needs at least 3 registrations" "$out/few.txt" || { cat "$out/few.txt"; fail "evaluate with 2 registrations"; }

# The weakest start, the template alone: a start model without components, every scan registered
# with it and judged; the round learns a model when at least 3 pass, and says so when fewer do.
if [ "$scale" = full ]; then
    "$sscape" bootstrap "$out/scans" --template-only --rounds 1 --components 2 -o "$out/template" > "$out/template.txt" 2>&1
    code=$?
    grep -q "from the template alone of the built-in model" "$out/template.txt" || { cat "$out/template.txt"; fail "the template-only start"; }
    "$sscape" info "$out/template/round_0/model.sscape" > "$out/template_info.txt" 2>&1 || fail "info on the template-only start"
    grep -q "^components:  0" "$out/template_info.txt" || { cat "$out/template_info.txt"; fail "the template-only start has components"; }
    for i in 1 2 3 4 5 6; do [ -s "$out/template/round_1/registrations/b$i.ply" ] || fail "template-only registration $i"; done
    [ "$code" -eq 0 ] || grep -q "a model needs at least 3" "$out/template.txt" || { cat "$out/template.txt"; fail "template-only bootstrap exited $code"; }
fi

# Refusals: a message, a non-zero exit.
expect() {  # expect CODE PATTERN ARGS...
    code=$1 pattern=$2; shift 2
    "$sscape" bootstrap "$@" > "$out/bad.txt" 2>&1
    got=$?
    if [ "$got" -ne "$code" ] || ! grep -q -e "$pattern" "$out/bad.txt"; then cat "$out/bad.txt"; fail "bootstrap $* exited $got (expected $code) or lacks '$pattern'"; fi
}
printf 'scan,decision\nnobody,reject\n' > "$out/unknown.csv"
expect 1 "the decisions name scan 'nobody', which is not in the collection" "$out/scans" --decisions "$out/unknown.csv" -o "$out/bad"
printf 'scan,decision\nb1,maybe\n' > "$out/maybe.csv"
expect 1 "maybe.csv:2: expected scan,accept|reject" "$out/scans" --decisions "$out/maybe.csv" -o "$out/bad"
printf 'scan,age\nb1,31\n' > "$out/few_ages.csv"
expect 1 "few_ages.csv has no row for scan b2" "$out/scans" --attributes "$out/few_ages.csv" -o "$out/bad"
expect 1 "posture model" "$out/scans" --posture-model "$out/ages.csv" -o "$out/bad"
"$sscape" make-test-model -o "$out/other_rig.sscape" --components 4 > /dev/null || fail "make-test-model"
expect 1 "does not share the mesh, skeleton and skinning" "$out/scans" --posture-model "$out/other_rig.sscape" -o "$out/bad"
[ ! -e "$out/bad" ] || fail "a refused bootstrap wrote $out/bad"
mkdir -p "$out/two" && cp "$out/scans/b1.ply" "$out/scans/b2.ply" "$out/two/"
expect 2 "holds 2 scans (.ply or .obj); bootstrapping needs at least 3" "$out/two" -o "$out/bad"
echo "bootstrap: one round learned, resumed, decided by a person; refusals clear"
