"""sscape.pipeline on a LocalCluster of 2 worker processes: the same files as the serial command
line for a handful of simulated scans, a broken scan failing alone, an interrupted run resumed,
and bootstrapping. Needs libsscape_offline, Debian's python3-distributed and the sscape command
line (SSCAPE_CLI) that makes the scans and the serial reference."""
import csv
import filecmp
import json
import struct
import os
import shutil
import subprocess
import sys

import pytest

import sscape
from sscape import _native

if not _native.has_offline:
    pytest.skip(f"{_native.library_path} is the runtime alone (the pipeline needs libsscape_offline)", allow_module_level=True)
distributed = pytest.importorskip("distributed", reason="python3-distributed is not installed")
CLI = os.environ.get("SSCAPE_CLI")
if not CLI:
    pytest.skip("SSCAPE_CLI (the sscape command line, for the serial reference) is not set", allow_module_level=True)

from sscape import pipeline  # noqa: E402

SCANS = 4


def run(*args):
    done = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    """Four simulated booth-like scans of posed bodies the model cannot represent exactly (bumps),
    with landmarks, and a broken file."""
    folder = tmp_path_factory.mktemp("scans")
    for seed in range(1, SCANS + 1):
        run("simulate", "-o", folder / f"p{seed}", "--seed", seed, "--points", 8000, "--pose-amount", 0.2)
        (folder / f"p{seed}_truth.obj").unlink()
    (folder / "broken.ply").write_text("ply\nthis is not a scan\n")
    return folder


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as c:
        yield c


def without_times(path):
    report = json.loads(path.read_text())
    for key in ("seconds", "fit_seconds"):
        report.pop(key)
    return report


@pytest.fixture(scope="module")
def registered(scans, client, tmp_path_factory):
    """The collection registered once on the cluster: (its folder, the run's result)."""
    out = tmp_path_factory.mktemp("registered")
    return out, pipeline.register_collection(scans, out_dir=out, client=client, progress=False)


def test_register_collection_equals_the_serial_command_line(scans, registered, tmp_path):
    out, result = registered
    assert sorted(result) == ["broken"] + [f"p{i}_scan" for i in range(1, SCANS + 1)]
    assert result["broken"]["status"] == "failed"
    assert "not a PLY file" in result["broken"]["error"]
    assert not (out / "broken.ply").exists()
    manifest = json.loads((out / "pipeline" / "manifest.json").read_text())
    assert manifest["scans"] == json.loads(json.dumps(result)) and manifest["finished"]
    assert len({s["pid"] for s in result.values() if "pid" in s}) == 2  # both worker processes worked
    serial = tmp_path / "serial"
    serial.mkdir()
    assert all(result[f"p{i}_scan"]["status"] == "registered" for i in range(1, SCANS + 1)), result
    for i in (1, 4):  # two of them against sscape register (every one runs the same code)
        name = f"p{i}_scan"
        run("register", scans / f"{name}.ply", "--landmarks", scans / f"p{i}.lnd", "-o", serial / f"{name}.ply", "--report", serial / f"{name}.json")
        assert filecmp.cmp(out / f"{name}.ply", serial / f"{name}.ply", shallow=False), name
        assert without_times(out / f"{name}.json") == without_times(serial / f"{name}.json"), name


def test_an_interrupted_run_resumes(scans, registered, client, tmp_path):
    out = tmp_path / "registered"
    shutil.copytree(registered[0], out)
    first = registered[1]
    kept = {n: (out / f"{n}.ply").read_bytes() for n, s in first.items() if s["status"] == "registered"}
    # As if stopped after two scans: the last two never written (a report is written after its mesh).
    for name in ("p3_scan", "p4_scan"):
        (out / f"{name}.json").unlink()
        (out / f"{name}.ply").unlink()
    (out / "p2_scan.json").unlink()  # stopped between a mesh and its report: made again
    again = pipeline.register_collection(scans, out_dir=out, client=client, progress=False)
    assert {n for n, s in again.items() if s["status"] == "registered"} == {"p2_scan", "p3_scan", "p4_scan"}
    assert {n for n, s in again.items() if s["status"] == "reused"} == {"p1_scan"}
    assert again["broken"]["status"] == "failed"
    for name, data in kept.items():
        assert (out / f"{name}.ply").read_bytes() == data, name


def test_a_killed_run_resumes(scans, client, tmp_path):
    """The command line killed (with its cluster) once two scans are done; run again, it reuses them."""
    import signal
    import time
    out = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-m", "sscape.pipeline", "register", str(scans), "-o", str(out), "--workers", "2", "--quiet"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    done = []
    deadline = time.time() + 300
    while time.time() < deadline and proc.poll() is None:
        try:
            manifest = json.loads((out / "pipeline" / "manifest.json").read_text())
            done = [n for n, s in manifest["scans"].items() if s["status"] == "registered"]
        except (OSError, ValueError):
            pass
        if len(done) >= 2:
            break
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    assert len(done) >= 2, "the run ended before it could be killed"
    again = pipeline.register_collection(scans, out_dir=out, client=client, progress=False)
    reused = {n for n, s in again.items() if s["status"] == "reused"}
    assert set(done) <= reused
    assert all(s["status"] in ("reused", "registered") for n, s in again.items() if n != "broken")
    assert not [p for p in out.iterdir() if p.name.startswith(".")], "a partial file was left"


def test_bootstrap_equals_the_serial_command_line(scans, client, tmp_path):
    """With the segment shape spaces in the registrations' model fit: the cluster's tasks register
    as the library's own bootstrapping does, with the same settings."""
    out, serial = tmp_path / "bootstrap", tmp_path / "serial"
    rows = pipeline.bootstrap(str(scans), None, 1, str(out), client=client, components=2, segment_components=2, fit_segments=True,
                              progress=False, log=lambda line: None)
    assert len(rows) == 1 and int(rows[0]["failed"]) == 1 and int(rows[0]["accepted"]) >= 3
    report = json.loads((out / "round_1" / "registrations" / "p1_scan.json").read_text())
    assert report["fit_segments"] is True and len(report["fit"]["segment_shape"]) > 0
    run("bootstrap", scans, "-o", serial, "--rounds", 1, "--components", 2, "--segment-components", 2, "--fit-segments")
    for f in ("model.sscape", "round_0/model.sscape", "round_1/model.sscape", "round_1/decisions.csv", "round_1/contact_sheet_01.png"):
        assert filecmp.cmp(out / f, serial / f, shallow=False), f
    for i in range(1, SCANS + 1):
        f = f"round_1/registrations/p{i}_scan.ply"
        assert filecmp.cmp(out / f, serial / f, shallow=False), f
    manifest = json.loads((out / "round_1" / "pipeline" / "manifest.json").read_text())
    assert manifest["scans"]["broken"]["status"] == "failed"
    learned = sscape.Model.from_file(out / "model.sscape")
    assert learned.shape_count == 2
    # Its segment shape spaces, as the package reads them.
    assert [s.name for s in learned.segments] == ["head", "arm_l", "arm_r", "torso", "leg_l", "leg_r"]
    vertices, weights = learned.segment_vertices("head")
    assert vertices.dtype.name == "uint32" and weights.dtype.name == "float32"
    assert vertices.size == learned.segments[0].vertex_count and vertices.max() < learned.vertex_count
    assert weights.min() > 0 and weights.max() <= 1 and (weights == 1).any()


def test_bootstrap_settings_name_the_posture_normalization(scans, tmp_path):
    for posture in ("skeleton", "none", "laplacian"):
        pipeline.Bootstrapping(str(scans), str(tmp_path / posture), posture=posture, components=2).close()
        assert not (tmp_path / posture).exists()  # settings only: nothing written yet
    with pytest.raises(ValueError, match="laplacian"):
        pipeline.Bootstrapping(str(scans), str(tmp_path / "x"), posture="wuhrer")


def test_two_bootstraps_into_one_folder_the_second_is_refused(scans, tmp_path):
    # Both once said "wrote model.sscape" and the folder kept only the second's model.
    out = tmp_path / "shared"
    first = pipeline.Bootstrapping(str(scans), str(out), components=2)
    second = pipeline.Bootstrapping(str(scans), str(out), components=3)
    first.prepare()
    with pytest.raises(sscape.SscapeError, match="is in use by another bootstrap") as e:
        second.prepare()
    assert e.value.status_name == "SSC_ERROR_IO"
    first.close()  # the folder is free again
    second.prepare()
    second.close()


def test_a_folder_with_stale_links_and_a_name_that_is_not_utf8_lists(tmp_path):
    # A link to nothing and a loop of links are left out with a warning naming them (they once
    # stopped the listing); a file name that is not UTF-8 is kept as the bytes it is.
    (tmp_path / "a.ply").write_text("x")
    odd = os.fsencode(str(tmp_path)) + b"/\xe4rger.ply"
    with open(odd, "w") as f:
        f.write("x")
    os.symlink("nowhere.ply", tmp_path / "stale.ply")
    os.symlink("loop_b.ply", tmp_path / "loop_a.ply")
    os.symlink("loop_a.ply", tmp_path / "loop_b.ply")
    with pytest.warns(UserWarning) as said:
        found = pipeline.list_scans(tmp_path)
    assert sorted(os.fsencode(s.path) for s in found) == sorted([os.fsencode(str(tmp_path / "a.ply")), odd])
    messages = [str(w.message) for w in said]
    assert any("stale.ply left out of the scans: a link to nothing" in m for m in messages), messages
    assert sum("symbolic links" in m for m in messages) == 2, messages


def test_settings_out_of_range_are_refused_before_anything_is_written(tmp_path):
    # --rounds 0 once wrote round_0 then failed on a missing rounds.csv, --components -5 reached the
    # library as 4294967291, --workers -1 waited forever for a worker.
    out = tmp_path / "out"
    for settings, word in (({"rounds": 0}, "rounds"), ({"components": -5}, "components"), ({"workers": -1}, "workers"),
                           ({"segment_components": 2.5}, "segment_components"), ({"threads_per_task": 0}, "threads_per_task")):
        with pytest.raises(ValueError, match=word):
            pipeline.bootstrap(str(tmp_path), out_dir=str(out), progress=False, **settings)
    for collection in (pipeline.register_collection, pipeline.fit_collection):
        with pytest.raises(ValueError, match="workers"):
            collection(str(tmp_path), None, str(out), workers=-1, progress=False)
    assert not out.exists()
    for argv, message in ((["bootstrap", str(tmp_path), "-o", str(out), "--components", "-5"], "-5 is not in 1..1000"),
                          (["bootstrap", str(tmp_path), "-o", str(out), "--rounds", "0"], "0 is not in 1..100"),
                          (["register", str(tmp_path), "-o", str(out), "--workers", "-1"], "-1 is not in 1..4096"),
                          (["fit", str(tmp_path), "-o", str(out), "--components", "x"], "'x' is not a whole number")):
        done = subprocess.run([sys.executable, "-m", "sscape.pipeline", *argv], capture_output=True, text=True, timeout=60)
        assert done.returncode == 2 and message in done.stderr, (argv, done.returncode, done.stderr)
    assert not out.exists()


def test_a_task_past_its_timeout_fails_alone_and_writes_nothing(scans, client, tmp_path):
    # There was no per-task limit: one scan whose call took too long held the whole run.
    two = [(scans / f"p{i}_scan.ply", scans / f"p{i}.lnd") for i in (1, 2)]
    for collection, suffix in ((pipeline.register_collection, ".ply"), (pipeline.fit_collection, ".obj")):
        out = tmp_path / collection.__name__
        done = collection(two, None, str(out), client=client, progress=False, task_timeout=0.01)
        assert sorted(done) == ["p1_scan", "p2_scan"]
        for name, scan in done.items():
            assert scan["status"] == "failed" and "task timeout of 0.01 s" in scan["error"], scan
            assert not (out / (name + suffix)).exists() and not (out / (name + ".json")).exists()
    for bad in (0, -1, float("nan"), float("inf"), True, "10"):
        with pytest.raises(ValueError, match="task_timeout"):
            pipeline.register_collection(two, None, str(tmp_path / "never"), progress=False, task_timeout=bad)
    assert not (tmp_path / "never").exists()
    done = subprocess.run([sys.executable, "-m", "sscape.pipeline", "fit", str(scans), "-o", str(tmp_path / "never"), "--task-timeout", "0"],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and "not in (0, 1e6] seconds" in done.stderr, done.stderr


def test_a_scan_named_manifest_keeps_its_own_outputs(scans, client, tmp_path):
    # The manifest once replaced manifest.ply's report: fit said "2 fitted", measure measured 1,
    # register registered it again on every run.
    folder = tmp_path / "scans"
    folder.mkdir()
    for i, name in ((1, "manifest"), (2, "other")):
        shutil.copy(scans / f"p{i}_scan.ply", folder / f"{name}.ply")
        shutil.copy(scans / f"p{i}.lnd", folder / f"{name}.lnd")
    out = tmp_path / "registered"
    first = pipeline.register_collection(folder, out_dir=out, client=client, progress=False)
    assert {n: s["status"] for n, s in first.items()} == {"manifest": "registered", "other": "registered"}
    assert json.loads((out / "manifest.json").read_text())["scan"].endswith("manifest.ply")  # its report
    again = pipeline.register_collection(folder, out_dir=out, client=client, progress=False)
    assert {n: s["status"] for n, s in again.items()} == {"manifest": "reused", "other": "reused"}
    fits = tmp_path / "fits"
    fitted = pipeline.fit_collection(folder, out_dir=fits, client=client, iterations=30, progress=False)
    assert {n: s["status"] for n, s in fitted.items()} == {"manifest": "fitted", "other": "fitted"}
    measured = pipeline.measure_collection(fits, client=client, progress=False)
    assert {n: s["status"] for n, s in measured.items()} == {"manifest": "measured", "other": "measured"}
    # Parameters of another model are refused, not measured as another body.
    params = json.loads((fits / "other.json").read_text())
    params["model_digest"] = "0123456789abcdef"
    (fits / "other.json").write_text(json.dumps(params))
    measured = pipeline.measure_collection(fits, client=client, progress=False)
    assert measured["other"]["status"] == "failed" and "fitted with the model of digest 0123456789abcdef" in measured["other"]["error"]


def test_scans_whose_names_are_not_utf8_are_registered_fitted_and_measured(scans, client, tmp_path):
    # A name the file system allows but UTF-8 does not ("\xe4rger", Latin-1) once stopped the
    # pipeline with "'utf-8' codec can't decode byte 0xe4" and no file named; a failure's message
    # naming such a file must reach the user too.
    folder = tmp_path / "scans"
    folder.mkdir()
    odd = os.fsencode(str(folder)) + b"/\xe4rger"
    shutil.copy(scans / "p1_scan.ply", odd + b".ply")
    shutil.copy(scans / "p1.lnd", odd + b".lnd")
    with open(odd + b"_broken.ply", "w") as f:
        f.write("ply\nthis is not a scan\n")
    name, broken = os.fsdecode(b"\xe4rger"), os.fsdecode(b"\xe4rger_broken")
    out = tmp_path / "registered"
    done = pipeline.register_collection(folder, out_dir=out, client=client, progress=False)
    assert {n: s["status"] for n, s in done.items()} == {name: "registered", broken: "failed"}, done
    assert "\\xe4rger_broken.ply" in done[broken]["error"], done[broken]["error"]
    assert os.path.exists(os.fsencode(str(out)) + b"/\xe4rger.ply")
    again = pipeline.register_collection(folder, out_dir=out, client=client, progress=False)
    assert again[name]["status"] == "reused"
    fits = tmp_path / "fits"
    fitted = pipeline.fit_collection(folder, out_dir=fits, client=client, iterations=30, progress=False)
    assert fitted[name]["status"] == "fitted" and fitted[broken]["status"] == "failed"
    measured = pipeline.measure_collection(fits, client=client, progress=False)
    assert {n: s["status"] for n, s in measured.items()} == {name: "measured"}
    with open(fits / "measurements.csv", "rb") as f:
        assert f.read().splitlines()[1].startswith(b"\xe4rger,")  # the file's own name
    # Bootstrapping's tasks name the same files (it needs three scans).
    shutil.copy(scans / "p2_scan.ply", folder / "plain.ply")
    boot = pipeline.Bootstrapping(str(folder), str(tmp_path / "boot"), components=2)
    boot.prepare()
    assert sorted(boot.scan_names) == sorted([name, broken, "plain"])
    assert sorted(os.fsencode(j["scan"]) for j in boot.jobs(1)) == sorted([odd + b".ply", odd + b"_broken.ply", os.fsencode(str(folder / "plain.ply"))])
    boot.close()


def test_fit_and_measure_collections_equal_the_serial_command_line(scans, client, tmp_path):
    out, serial = tmp_path / "fits", tmp_path / "serial"
    serial.mkdir()
    fits = pipeline.fit_collection(scans, out_dir=out, client=client, iterations=60, progress=False)
    assert fits["broken"]["status"] == "failed" and "not a PLY file" in fits["broken"]["error"]
    assert not (out / "broken.obj").exists() and not (out / "broken.json").exists()
    for i in (1, 4):  # two of them against sscape fit
        name = f"p{i}_scan"
        assert fits[name]["status"] == "fitted", fits[name]
        run("fit", "--points", scans / f"{name}.ply", "--landmarks", scans / f"p{i}.lnd", "--iterations", 60, "-o", serial / f"{name}.obj",
            "--params", serial / f"{name}.json")
        assert filecmp.cmp(out / f"{name}.obj", serial / f"{name}.obj", shallow=False), name
        ours, theirs = json.loads((out / f"{name}.json").read_text()), json.loads((serial / f"{name}.json").read_text())
        ours["report"].pop("seconds"), theirs["report"].pop("seconds")
        assert ours == theirs, name
    # Again: every fit kept (the same files and settings), the broken scan tried and failed again.
    bodies = {n: (out / f"{n}.obj").read_bytes() for n in fits if n != "broken"}
    again = pipeline.fit_collection(scans, out_dir=out, client=client, iterations=60, progress=False)
    assert {n for n, r in again.items() if r["status"] == "reused"} == set(bodies)
    assert again["broken"]["status"] == "failed"
    assert all((out / f"{n}.obj").read_bytes() == b for n, b in bodies.items())
    # Other settings fit again.
    assert pipeline.fit_collection([scans / "p1_scan.ply"], out_dir=out, client=client, iterations=61, progress=False)["p1_scan"]["status"] == "fitted"
    measured = pipeline.measure_collection(str(out), client=client, progress=False)
    assert sorted(measured) == [f"p{i}_scan" for i in range(1, SCANS + 1)]  # the failed fit wrote no parameters
    rows = list(csv.DictReader((out / "measurements.csv").open()))
    assert [r["scan"] for r in rows] == sorted(measured)
    shape = json.loads((out / "p4_scan.json").read_text())["shape"]
    values = json.loads(run("measure", "--shape", ",".join(repr(x) for x in shape), "--json"))["bodies"][0]["values"]
    row = next(r for r in rows if r["scan"] == "p4_scan")
    f32 = lambda x: struct.unpack("f", struct.pack("f", float(x)))[0]
    for name, value in values.items():
        column = next(c for c in row if c.startswith(name + "_"))
        assert f32(row[column]) == f32(value), name
    assert 1.4 < float(row["stature_m"]) < 2.1


def test_the_command_line(scans, tmp_path):
    # Two of the scans and the broken file: the command's counts, exit code and messages.
    few = tmp_path / "few"
    few.mkdir()
    for name in ("p1_scan.ply", "p1.lnd", "p2_scan.ply", "p2.lnd", "broken.ply"):
        shutil.copy(scans / name, few / name)
    out = tmp_path / "cli"
    env = dict(os.environ)
    done = subprocess.run([sys.executable, "-m", "sscape.pipeline", "register", str(few), "-o", str(out), "--workers", "2", "--quiet"],
                          capture_output=True, text=True, env=env)
    assert done.returncode == 1, done.stdout + done.stderr  # the broken scan
    assert "3 scans: 2 registered, 0 reused, 1 failed" in done.stdout, done.stdout
    assert "failed: broken:" in done.stderr
    assert all((out / f"p{i}_scan.ply").exists() for i in (1, 2))
    bad = subprocess.run([sys.executable, "-m", "sscape.pipeline", "register", str(tmp_path / "none"), "-o", str(out)],
                         capture_output=True, text=True, env=env)
    assert bad.returncode == 1 and "cannot list the folder" in bad.stderr, bad.stderr
