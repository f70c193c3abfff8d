"""python3 -m sscape.pipeline: scan collections on a Dask cluster from the command line."""
from __future__ import annotations

import argparse
import sys

from ..errors import SscapeError


def _whole(lo: int, hi: int):
    """An argparse type: a whole number in lo..hi (a usage error, exit 2, otherwise)."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
        if not lo <= value <= hi:
            raise argparse.ArgumentTypeError(f"{value} is not in {lo}..{hi}")
        return value
    return parse


def _seconds(text: str) -> float:
    """An argparse type: seconds in (0, 1e6]."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not 0 < value <= 1e6:
        raise argparse.ArgumentTypeError(f"{text} is not in (0, 1e6] seconds")
    return value


def _cluster_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scheduler", metavar="tcp://HOST:8786", help="a running Dask scheduler (default: a local cluster on this machine)")
    p.add_argument("--workers", type=_whole(1, 4096), metavar="N", help="processes of the local cluster (default: one per core)")
    p.add_argument("--units", choices=["m", "cm", "mm"], help="units of the scans and landmark files (default: metres, .lnd millimetres)")
    p.add_argument("--up", choices=["x", "y", "z", "-x", "-y", "-z"], help="the scans' up axis (default y)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--task-timeout", type=_seconds, metavar="SECONDS",
                   help="stop a scan's task after this long and record it as failed (default: no limit)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m sscape.pipeline", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("register", help="register every scan of a folder to the model's template (as sscape register)")
    r.add_argument("scans", metavar="SCANS_DIR")
    r.add_argument("-o", "--output", required=True, metavar="OUT_DIR")
    r.add_argument("--model", metavar="MODEL.sscape", help="default: the built-in model")
    r.add_argument("--png", action="store_true", help="also draw each scan beside its registration (NAME.png)")
    r.add_argument("--segments", action=argparse.BooleanOptionalAction, default=True,
                   help="the model's segment shape spaces join each model fit (default; as sscape register --segments)")
    _cluster_options(r)
    b = sub.add_parser("bootstrap", help="learn a model from a folder of scans by rounds (as sscape bootstrap)")
    b.add_argument("scans", metavar="SCANS_DIR")
    b.add_argument("-o", "--output", required=True, metavar="OUT_DIR")
    b.add_argument("--init", metavar="MODEL.sscape", help="the starting model (default: the built-in model)")
    b.add_argument("--rounds", type=_whole(1, 100), default=3)
    b.add_argument("--components", type=_whole(1, 1000), default=20)
    b.add_argument("--posture", choices=["skeleton", "none", "laplacian"], default="skeleton")
    b.add_argument("--posture-model", metavar="MODEL.sscape|own",
                   help="skeleton: the model whose fits to the scans unpose the registrations (default: the built-in model; "
                        "own: each round's own fits; as sscape bootstrap)")
    b.add_argument("--template-only", action="store_true")
    b.add_argument("--scale", action="store_true")
    b.add_argument("--segment-components", type=_whole(0, 1000), default=0)
    b.add_argument("--fit-segments", action=argparse.BooleanOptionalAction, default=True,
                   help="register with the model's segment shape spaces in the model fit (default; as sscape bootstrap)")
    b.add_argument("--decisions", metavar="FILE.csv")
    b.add_argument("--attributes", metavar="FILE.csv")
    b.add_argument("--name")
    b.add_argument("--license")
    _cluster_options(b)
    f = sub.add_parser("fit", help="fit the model to every scan of a folder (as sscape fit --points --landmarks --params)")
    f.add_argument("scans", metavar="SCANS_DIR")
    f.add_argument("-o", "--output", required=True, metavar="OUT_DIR")
    f.add_argument("--model", metavar="MODEL.sscape", help="default: the built-in model")
    f.add_argument("--hands", action="store_true", help="use the hand landmarks too")
    f.add_argument("--components", type=_whole(0, 1000), default=0, help="shape components fitted (default: all)")
    f.add_argument("--format", choices=["obj", "ply", "glb"], default="obj", help="the fitted bodies' files (default obj)")
    _cluster_options(f)
    m = sub.add_parser("measure", help="measure every fitted body of a folder (as sscape measure --shape)")
    m.add_argument("fits", metavar="FITS_DIR", help="what fit wrote (NAME.json parameters)")
    m.add_argument("-o", "--output", metavar="OUT.csv", help="default: FITS_DIR/measurements.csv")
    m.add_argument("--model", metavar="MODEL.sscape", help="the model the fits were made with (default: the built-in model)")
    m.add_argument("--scheduler", metavar="tcp://HOST:8786")
    m.add_argument("--workers", type=_whole(1, 4096), metavar="N")
    m.add_argument("--quiet", action="store_true")
    a = parser.parse_args(argv)
    from . import bootstrap, fit_collection, measure_collection, register_collection
    try:
        if a.command == "register":
            scans = register_collection(a.scans, a.model, a.output, units=a.units, up=a.up, pictures=a.png, scheduler=a.scheduler,
                                        workers=a.workers, progress=not a.quiet, fit_segments=a.segments,
                                        task_timeout=a.task_timeout)
            failed = {n: s for n, s in scans.items() if s["status"] == "failed"}
            done = sum(s["status"] == "registered" for s in scans.values())
            print(f"{len(scans)} scans: {done} registered, {len(scans) - done - len(failed)} reused, {len(failed)} failed; "
                  f"{a.output}/pipeline/manifest.json")
            for name, s in failed.items():
                print(f"failed: {name}: {s['error']}", file=sys.stderr)
            return 1 if failed else 0
        if a.command in ("fit", "measure"):
            if a.command == "fit":
                scans = fit_collection(a.scans, a.model, a.output, units=a.units, hands=a.hands, components=a.components,
                                       body_format=a.format, scheduler=a.scheduler, workers=a.workers, progress=not a.quiet,
                                       task_timeout=a.task_timeout)
                where = f"{a.output}/pipeline/manifest.json"
            else:
                scans = measure_collection(a.fits, a.model, a.output, scheduler=a.scheduler, workers=a.workers, progress=not a.quiet)
                where = a.output or f"{a.fits}/measurements.csv"
            failed = {n: s for n, s in scans.items() if s["status"] == "failed"}
            print(f"{len(scans)} scans: {len(scans) - len(failed)} {a.command == 'fit' and 'fitted' or 'measured'}, {len(failed)} failed; {where}")
            for name, s in failed.items():
                print(f"failed: {name}: {s['error']}", file=sys.stderr)
            return 1 if failed else 0
        rows = bootstrap(a.scans, a.init, a.rounds, a.output, scheduler=a.scheduler, workers=a.workers, progress=not a.quiet,
                         components=a.components, posture=a.posture, template_only=a.template_only, scale=a.scale,
                         segment_components=a.segment_components, fit_segments=a.fit_segments, units=a.units, up=a.up, decisions=a.decisions,
                         attributes=a.attributes, name=a.name, license=a.license,
                         posture_model="" if a.posture_model == "own" else a.posture_model, task_timeout=a.task_timeout)
        for row in rows:
            print(f"round {row['round']}: {row['accepted']} accepted, {row['rejected']} rejected, {row['failed']} failed")
        print(f"wrote {a.output}/model.sscape")
        return 0
    except (SscapeError, OSError, ValueError) as e:
        print(f"sscape.pipeline {a.command}: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
