#!/usr/bin/env bash
# Configures and builds the command line without the training tools (SSCAPE_BUILD_TRAINING=OFF), as
# a studio that registers and fits scans but never trains a model would: `sscape register` and
# `sscape fit` are there (scan files are a stage of their own, below learning), `train` and `learn`
# say they are not in this build.
# usage: without_training.sh SOURCE_DIR WORK_DIR
set -euo pipefail
source="$1" work="$2"
rm -rf "$work"
cmake -S "$source" -B "$work" -DCMAKE_BUILD_TYPE=Release -DSSCAPE_BUILD_TRAINING=OFF -DSSCAPE_BUILD_TESTS=OFF \
      -DSSCAPE_BUILD_BENCHMARKS=OFF -DSSCAPE_BUILD_SAMPLES=OFF > "$work.configure.log"
cmake --build "$work" -j "${JOBS:-2}" --target sscape_cli > "$work.build.log"
sscape="$work/bin/sscape"
[ ! -e "$work/sdk/libsscape_training.a" ] || { echo "the training tools were built"; exit 1; }
"$sscape" register --help | grep -q -- "--landmarks" || { echo "sscape register is missing"; exit 1; }
"$sscape" --help | grep -q "register .*deform the model's template onto a raw body scan, vertex for vertex" || { echo "sscape register is not listed"; exit 1; }
"$sscape" --help | grep -q "train .*(not in this build)" || { echo "sscape train should say it is not in this build"; exit 1; }
# A real registration, end to end: a simulated scan of the default model.
"$sscape" simulate --seed 3 -o "$work/sim" > /dev/null
"$sscape" register "$work/sim_scan.ply" --landmarks "$work/sim.lnd" -o "$work/registered.ply" --report "$work/registered.json" > "$work/register.log"
[ -s "$work/registered.ply" ] && [ -s "$work/registered.json" ] || { echo "sscape register wrote nothing"; exit 1; }
echo "built without training: sscape register and fit there, train and learn not"
