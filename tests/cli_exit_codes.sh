#!/bin/sh
# The command line's exit codes and messages: 0 done (and for --help, --version), 2 a usage error
# naming the bad option or value, 1 a failure of the work itself (a file that is no model).
# usage: cli_exit_codes.sh SSCAPE OUT_DIR
set -u
sscape=$1 out=$2
fails=0
expect() {  # expect CODE PATTERN ARGS...: the exit code, and PATTERN in stdout+stderr
    code=$1 pattern=$2; shift 2
    "$sscape" "$@" > "$out/exit.txt" 2>&1
    got=$?
    if [ "$got" -ne "$code" ] || ! grep -q -e "$pattern" "$out/exit.txt"; then
        echo "FAIL: sscape $* exited $got (expected $code) or lacks '$pattern':"; cat "$out/exit.txt"; fails=1
    fi
}
expect 0 "^sscape [0-9]*\.[0-9]*\.[0-9]* (library .*default model sscape-default" --version
expect 0 "Subcommands:" --help
for command in info synth measure fit register simulate train learn bootstrap evaluate make-test-model; do
    expect 0 "Usage: sscape $command" "$command" --help
    expect 0 "^  sscape $command " "$command" --help  # an example to start from
done
# A typo gets the nearest name.
expect 2 "unknown command 'synt' (did you mean 'synth'?)" synt
expect 2 "'--seeed' (did you mean '--seed'?)" synth --random 2 --seeed 3 -o "$out/x.obj"
expect 0 "--units m|cm|mm" fit --help
expect 2 "A subcommand is required"
expect 2 "unknown command 'frobnicate'; the commands: bootstrap, evaluate, fit, info" frobnicate
expect 2 "sscape synth: The following argument was not expected: --bogus" synth --bogus -o "$out/x.obj"
expect 2 "sscape fit: --units: furlong not in {m,cm,mm}" fit --landmarks "$out/exit.txt" --units furlong -o "$out/x.obj"
expect 2 "sscape synth: --random: Value 0 not in range 1 to 10000" synth --random 0 -o "$out/x.obj"
expect 2 "sscape synth: --shape excludes --random" synth --random 2 --shape 1 -o "$out/x.obj"
expect 2 "sscape synth: --output is required" synth
expect 2 "sscape synth: --lod: the model has no level 'proxy9' (its levels: 0 full (13380 vertices), 1 simplified" synth --lod proxy9 -o "$out/x.obj"
expect 2 "sscape synth: --lod: the model has no level '4'" synth --lod 4 -o "$out/x.obj"
expect 2 "sscape synth: --landmarks-png draws the full mesh: leave --lod out" synth --lod 3 --landmarks-png "$out/l.png" -o "$out/x.obj"
expect 0 "wrote 1 body of 741 vertices, 1460 triangles (level of detail 3, proxy741)" synth --lod proxy741 -o "$out/lod.glb"
expect 0 "wrote 1 body of 741 vertices" synth --lod 3 -o "$out/lod.obj"
expect 0 "  3 proxy741        741 vertices" info
expect 2 "sscape register: -o: the registered mesh is written as .obj or .ply" register "$out/exit.txt" -o "$out/x.glb"
expect 2 "sscape simulate: --noise: nan is outside\|sscape simulate: --noise: 'nan' is not a finite number" simulate --noise nan -o "$out/x"
expect 2 "sscape synth: --shape: 'abc' is not a finite number" synth --shape 1,abc -o "$out/x.obj"
expect 2 "Run 'sscape synth --help' for the options" synth --shape 1,abc -o "$out/x.obj"
expect 1 "sscape info: cannot load" info "$out/exit.txt"
[ "$fails" -eq 0 ] && echo "exit codes and messages as documented"
