#!/bin/sh
# `register` and `fit` on what is no person, or with landmarks that disagree with the scan, fail
# with a reason and write nothing (issue 47, item 2): once a plane registered "100 % within 2 mm",
# two clusters of identical points "registered" (fit: converged at 6.5 SD), and landmarks moved by
# half a metre, shifted 100 m or with left and right exchanged gave exit 0.
# usage: cli_register_garbage.sh SSCAPE OUT_DIR SIMULATED (a `sscape simulate` prefix: .lnd, _scan.ply)
set -u
sscape=$1 out=$2/cli_register_garbage sim=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
/usr/bin/python3 - "$out" "$sim.lnd" <<'PY' || fail "making the inputs"
import re, sys
import numpy as np
out, lnd = sys.argv[1], sys.argv[2]
rng = np.random.default_rng(3)
def ply(name, p):
    with open(f"{out}/{name}", "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n" % len(p))
        np.savetxt(f, p, fmt="%.5f")
n = 4000
ply("plane.ply", np.c_[rng.uniform(-0.4, 0.4, n), rng.uniform(0, 1.7, n), np.zeros(n)])
ply("clusters.ply", np.r_[np.tile([0, 0.2, 0], (n // 2, 1)), np.tile([0, 1.6, 0], (n // 2, 1))])
s = rng.normal(size=(n, 3))
ply("ball.ply", s / np.linalg.norm(s, axis=1)[:, None] * 0.15 + [0, 1.0, 0])
with open(f"{out}/ball.lnd", "w") as f:
    f.write("AUX =\n1 0 1 0 0 1150 0 Sellion\n2 0 2 0 150 1000 0 Lt. Acromion\n3 0 3 0 -150 1000 0 Rt. Acromion\n4 0 4 0 0 850 0 Crotch\nEND =\n")
lines = open(lnd).read().splitlines()
a = next(i for i, l in enumerate(lines) if l.startswith("AUX ="))
e = next(i for i, l in enumerate(lines) if l.startswith("END"))
def variant(name, change):
    rows = [change(k, l.split(None, 7)) for k, l in enumerate(lines[a + 1:e])]
    open(f"{out}/{name}.lnd", "w").write("\n".join(lines[:a + 1] + [" ".join(r) for r in rows] + lines[e:]) + "\n")
def moved(k, p, by):
    p[4:7] = ["%.2f" % (float(x) + d) for x, d in zip(p[4:7], by)]
    return p
variant("shifted", lambda k, p: moved(k, p, (100000, 0, 0)))
variant("swapped", lambda k, p: p[:7] + [re.sub(r"^(Lt|Rt)\.", lambda m: "Rt." if m.group(1) == "Lt" else "Lt.", p[7])])
variant("half_moved", lambda k, p: moved(k, p, 150 * (lambda d: d / np.linalg.norm(d))(rng.normal(size=3))) if k % 2 == 0 else p)
PY
refused() {  # refused WHAT PATTERN COMMAND...: exit 1, the reason, nothing written
    what=$1 pattern=$2; shift 2
    "$@" -o "$out/result.ply" > "$out/log.txt" 2>&1
    code=$?
    [ "$code" -eq 1 ] && grep -q -e "$pattern" "$out/log.txt" || { cat "$out/log.txt"; fail "$what: exit $code, or no '$pattern'"; }
    [ ! -e "$out/result.ply" ] && [ ! -e "$out/result.json" ] || fail "$what wrote its output"
}
refused "register a plane" "its points lie in one plane" "$sscape" register "$out/plane.ply" --report "$out/result.json"
refused "fit a plane" "its points lie in one plane" "$sscape" fit --points "$out/plane.ply"
refused "register two clusters" "points lie at only 2 places" "$sscape" register "$out/clusters.ply" --report "$out/result.json"
refused "fit two clusters" "points lie at only 2 places" "$sscape" fit --points "$out/clusters.ply"
refused "register landmarks 100 m away" "73 of 73 landmarks lie farther than 30 cm from every scan point" \
    "$sscape" register "$sim""_scan.ply" --landmarks "$out/shifted.lnd" --report "$out/result.json"
refused "register left and right exchanged" "left and right are exchanged" \
    "$sscape" register "$sim""_scan.ply" --landmarks "$out/swapped.lnd" --report "$out/result.json"
refused "register half the landmarks moved 150 mm" "landmarks lie more than 6 cm from where the model fitted to the scan has them" \
    "$sscape" register "$sim""_scan.ply" --landmarks "$out/half_moved.lnd" --report "$out/result.json"
refused "register a ball from its landmarks" "of the registered template lies within 20 mm of the scan: it missed the person" \
    "$sscape" register "$out/ball.ply" --landmarks "$out/ball.lnd" --start rigid --report "$out/result.json"
echo "register garbage: every non-person and bad landmark set refused"
