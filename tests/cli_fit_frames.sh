#!/bin/sh
# A capture whose middle frame is no person (a ball of points): `sscape fit --frames` says which
# frame failed and why as it goes, writes every other frame, not that one, and exits 1. And
# `sscape register` refuses to deform the template from a failed model fit (it used to exit 0); a scan
# of two people is refused.
# usage: cli_fit_frames.sh SSCAPE SCAN.ply OUT_DIR
set -u
sscape=$1 scan=$2 dir=$3/fit_frames
fail() { echo "FAIL: $1"; exit 1; }
rm -rf "$dir" && mkdir -p "$dir"
/usr/bin/python3 - "$dir/ball.ply" <<'PY' || fail "writing the ball"
import math, random, sys
random.seed(1)
points = []
for _ in range(4000):
    z, a = random.uniform(-1, 1), random.uniform(0, 2 * math.pi)
    r = math.sqrt(1 - z * z)
    points.append((0.3 * r * math.cos(a), 1.0 + 0.3 * r * math.sin(a), 0.3 * z))
with open(sys.argv[1], "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n" % len(points))
    for p in points:
        f.write("%.5f %.5f %.5f\n" % p)
PY
"$sscape" fit --points "$scan" --points "$dir/ball.ply" --points "$scan" --frames -o "$dir/fit.obj" > "$dir/out.txt" 2> "$dir/err.txt"
code=$?
[ "$code" = 1 ] || { cat "$dir/out.txt" "$dir/err.txt"; fail "exit $code, not 1"; }
grep -q "frame 1 of 3: fitted" "$dir/out.txt" || { cat "$dir/out.txt"; fail "frame 1's line"; }
grep -q "frame 2 of 3: failed: " "$dir/out.txt" || { cat "$dir/out.txt"; fail "frame 2's line"; }
grep -q "frame 3 of 3: fitted" "$dir/out.txt" || { cat "$dir/out.txt"; fail "frame 3's line"; }
grep -q "1 of 3 frames failed" "$dir/err.txt" || { cat "$dir/err.txt"; fail "the summary"; }
[ -s "$dir/fit.obj" ] && [ -s "$dir/fit_frame2.obj" ] || fail "the good frames written"
[ ! -e "$dir/fit_frame1.obj" ] || fail "the failed frame written"
"$sscape" register "$dir/ball.ply" -o "$dir/ball_registered.ply" > "$dir/reg.txt" 2>&1
code=$?
[ "$code" != 0 ] || { cat "$dir/reg.txt"; fail "register of a failed fit exits 0"; }
grep -q "the model fit to the scan failed (" "$dir/reg.txt" || { cat "$dir/reg.txt"; fail "the register message"; }
[ ! -e "$dir/ball_registered.ply" ] || fail "register wrote a mesh from a failed fit"
# Two people side by side (the scan twice, 1.2 m apart): the single fit fails, says the scan may hold
# more than the person, and writes nothing.
/usr/bin/python3 - "$scan" "$dir/two.ply" <<'PY' || fail "writing two people"
import struct, sys
raw = open(sys.argv[1], "rb").read()
end = raw.index(b"end_header\n") + len(b"end_header\n")
lines = raw[:end].decode().split("\n")
count = next(int(l.split()[2]) for l in lines if l.startswith("element vertex"))
names = []
for l in lines[lines.index(next(l for l in lines if l.startswith("element vertex"))) + 1:]:
    if not l.startswith("property float"):
        break
    names.append(l.split()[2])
rows = [struct.unpack_from("<%df" % len(names), raw, end + 4 * len(names) * i) for i in range(count)]
with open(sys.argv[2], "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex %d\n" % (2 * count) + "".join("property float %s\n" % n for n in names) + "end_header\n")
    for shift in (0.0, 1.2):
        for r in rows:
            f.write(" ".join("%.5f" % (v + shift if n == "x" else v) for n, v in zip(names, r)) + "\n")
PY
"$sscape" fit --points "$dir/two.ply" -o "$dir/two.obj" > "$dir/two_out.txt" 2> "$dir/two_err.txt"
code=$?
[ "$code" = 1 ] || { cat "$dir/two_out.txt" "$dir/two_err.txt"; fail "two people: exit $code, not 1"; }
grep -q "more than one person in the scan" "$dir/two_err.txt" || { cat "$dir/two_err.txt"; fail "two people: the message"; }
! grep -q "hard pose" "$dir/two_err.txt" || { cat "$dir/two_err.txt"; fail "two people: blamed on a hard pose"; }
[ ! -e "$dir/two.obj" ] || fail "two people: a fit written"
echo "fit frames: the failed frame reported and left out, the others written; register refuses a failed fit; two people refused"
