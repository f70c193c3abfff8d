#!/bin/sh
# bindings/python/README.md's "On several machines", run as written on one machine: the package in a
# venv as the README installs it, a scheduler and two workers (as two machines would start them) as
# separate processes on 127.0.0.1 with the venv's python and the README's options, then the
# pipeline's command against the scheduler on a simulated collection. Every process is stopped at
# the end, whatever happens.
# usage: dask_cluster.sh SOURCE_DIR OFFLINE_LIBRARY SSCAPE OUT_DIR
set -eu
src=$1 library=$2 sscape=$3 out=$4
rm -rf "$out" && mkdir -p "$out"
pids=""
stop() { for p in $pids; do kill "$p" 2> /dev/null || true; done; wait 2> /dev/null || true; }
trap stop EXIT
fail() { echo "FAIL: $*"; for f in "$out"/*.log; do echo "--- $f"; tail -n 20 "$f"; done; exit 1; }

# The installation (README, top): a venv over Debian's python3, the package with the built library.
cp -r "$src/bindings/python" "$out/package"
/usr/bin/python3 -m venv --system-site-packages "$out/.venv"
SSCAPE_LIBRARY="$library" "$out/.venv/bin/pip" install --quiet --no-build-isolation --no-index "$out/package"
python="$out/.venv/bin/python"
cd "$out"  # away from the source tree: the workers import the installed package

# Free ports on 127.0.0.1 for the scheduler, its dashboard and each worker and nanny.
set -- $(/usr/bin/python3 -c 'import socket
s = [socket.socket() for _ in range(6)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
scheduler_port=$1 dashboard_port=$2 worker_ports="$3 $4" nanny_ports="$5 $6"

"$python" -m distributed.cli.dask_scheduler --host 127.0.0.1 --port "$scheduler_port" --dashboard-address "127.0.0.1:$dashboard_port" \
    > "$out/scheduler.log" 2>&1 &
pids="$pids $!"
i=0
for w in $worker_ports; do
    i=$((i + 1))
    n=$(echo $nanny_ports | cut -d' ' -f$i)
    "$python" -m distributed.cli.dask_worker "tcp://127.0.0.1:$scheduler_port" --host 127.0.0.1 --nworkers 1 --nthreads 1 \
        --worker-port "$w" --nanny-port "$n" --no-dashboard > "$out/worker$i.log" 2>&1 &
    pids="$pids $!"
done
# Both workers registered with the scheduler (at most a minute).
"$python" - "$scheduler_port" <<'PY' || fail "the workers did not join the scheduler"
import sys
from distributed import Client
with Client(f"tcp://127.0.0.1:{sys.argv[1]}", timeout=60) as c:
    c.wait_for_workers(2, timeout=60)
    print("cluster:", len(c.scheduler_info()["workers"]), "workers")
PY

"$sscape" simulate --count 4 --seed 11 --points 6000 --pose-amount 0.2 -o "$out/collection" > "$out/simulate.log" 2>&1 || fail "simulate"
"$python" -m sscape.pipeline register "$out/collection/scans" -o "$out/registered" --scheduler "tcp://127.0.0.1:$scheduler_port" --quiet \
    > "$out/pipeline.log" 2>&1 || fail "the pipeline through the cluster"
cat "$out/pipeline.log"
grep -q "^4 scans: 4 registered, 0 reused, 0 failed" "$out/pipeline.log" || fail "4 scans registered"
"$python" - "$out/registered/pipeline/manifest.json" <<'PY' || fail "the manifest"
import json, sys
scans = json.load(open(sys.argv[1]))["scans"]
assert sorted(scans) == [f"sim_00{i}" for i in range(1, 5)], sorted(scans)
assert all(s["status"] == "registered" for s in scans.values()), scans
pids = {s["pid"] for s in scans.values()}
assert len(pids) == 2, f"{len(pids)} worker process(es) registered the scans"
print("both workers registered scans")
PY
for i in 1 2 3 4; do [ -s "$out/registered/sim_00$i.ply" ] || fail "no sim_00$i.ply"; done
echo "the README's cluster: a scheduler and two workers from the venv processed the folder"
