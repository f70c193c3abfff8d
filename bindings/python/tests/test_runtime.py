"""The Python package over the built library: every wrapped call, its errors, dtypes and shapes,
and that what numpy receives is exactly what the library computed."""
import logging
import os
import pathlib
import struct

import numpy as np
import pytest

import sscape


@pytest.fixture(scope="module")
def model():
    return sscape.Model()


def read_ply_vertices(path):
    """Positions of a binary little-endian PLY as the library writes it (x y z float first)."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    count = next(int(line.split()[2]) for line in header if line.startswith("element vertex"))
    props = []
    for line in header[header.index(next(l for l in header if l.startswith("element vertex"))) + 1:]:
        if not line.startswith("property"):
            break
        props.append(line.split()[1])
    assert props[:3] == ["float", "float", "float"]
    stride = sum({"float": 4, "uchar": 1, "int": 4, "uint": 4}[p] for p in props)
    out = np.empty((count, 3), np.float32)
    for i in range(count):
        out[i] = struct.unpack_from("<3f", data, end + i * stride)
    return out


def test_library_and_version():
    assert sscape.library_version().startswith(f"{sscape.ABI_MAJOR}.")
    assert sscape.library_path
    assert sscape.__version__


def test_every_public_member_says_what_it_is():
    """Every public class, function, method and property of the package has a docstring (help() is
    the reference for Python users)."""
    import importlib
    import inspect
    modules = [sscape]
    try:
        modules.append(importlib.import_module("sscape.pipeline"))
    except ImportError:  # python3-distributed absent: the pipeline is not there to document
        pass
    missing, seen = [], 0
    for module in modules:
        for name in module.__all__:
            obj = getattr(module, name)
            if not (inspect.isclass(obj) or inspect.isfunction(obj)):
                continue
            seen += 1
            if not inspect.getdoc(obj):
                missing.append(name)
            if inspect.isclass(obj):
                for member, value in vars(obj).items():
                    if member.startswith("_"):
                        continue
                    fn = value.fget if isinstance(value, property) else getattr(value, "__func__", value)
                    if inspect.isfunction(fn):
                        seen += 1
                        if not (fn.__doc__ or "").strip():
                            missing.append(f"{name}.{member}")
    assert seen > 60 and not missing, f"no docstring: {', '.join(missing)}"


def test_vertices_into_an_array_kept_across_bodies(model):
    with sscape.Body(model) as body:
        out = np.zeros((model.vertex_count, 3), np.float32)
        body.shape = [1.0, -0.5]
        got = body.get_vertices(out=out)
        assert got is out and np.array_equal(out, body.vertices)
        normals = np.empty_like(out)
        assert body.get_normals(out=normals) is normals and np.array_equal(normals, body.normals)
        assert body.get_vertices().shape == (model.vertex_count, 3)
        for bad in (np.zeros((model.vertex_count, 3), np.float64), np.zeros((10, 3), np.float32),
                    np.zeros((3, model.vertex_count), np.float32).T, [[0.0, 0.0, 0.0]]):
            with pytest.raises(ValueError, match="float32 array of shape"):
                body.get_vertices(out=bad)
        frozen = np.zeros((model.vertex_count, 3), np.float32)
        frozen.flags.writeable = False
        with pytest.raises(ValueError, match="writable"):
            body.get_vertices(out=frozen)


def test_default_model(model):
    assert model.vertex_count == 13380
    assert model.shape_count == 50
    assert model.joint_count == len(model.joint_names) == 53
    assert model.joint_names[0] == "Root"
    assert model.landmark_count == len(model.landmark_names) == 73
    tris = model.triangles
    assert tris.dtype == np.uint32 and tris.shape == (model.triangle_count, 3)
    assert tris.max() < model.vertex_count
    parents = model.joint_parents
    assert parents.dtype == np.int32 and parents[0] == -1 and (parents[1:] < np.arange(1, 53)).all()
    sd = model.shape_stddevs
    assert sd.dtype == np.float32 and sd.shape == (50,) and (np.diff(sd) <= 0).all()
    meta = model.metadata
    assert meta["name"] == "sscape-default" and meta["units"] == "m"
    assert [s.name for s in model.sliders][:2] == ["stature", "mass"]
    assert [(s.name, s.shape_count) for s in model.segments] == [(n, 10) for n in ("head", "arm_l", "arm_r", "torso", "leg_l", "leg_r")]
    assert "sscape-default" in repr(model)


def test_body_shape_pose_outputs(model):
    with sscape.Body(model) as body:
        np.testing.assert_array_equal(body.shape, np.zeros(50, np.float32))
        body.shape = [1.0, -0.5]
        shape = body.shape
        assert shape.dtype == np.float32 and shape[0] == 1.0 and shape[1] == -0.5 and not shape[2:].any()
        rest = body.rest_vertices
        posed = body.vertices
        assert posed.dtype == np.float32 and posed.shape == (13380, 3)
        np.testing.assert_allclose(posed, rest, atol=1e-5)  # the rest pose
        normals = body.normals
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-4)
        assert body.landmarks.shape == (73, 3)
        # An elbow bent: the hand moves, the feet do not.
        q = np.tile(np.array([0, 0, 0, 1], np.float32), (53, 1))
        elbow = model.joint_names.index("lowerarm_l")
        q[elbow] = [np.sin(0.4), 0, 0, np.cos(0.4)]
        body.set_pose(q, translation=[0, 0.1, 0])
        moved = body.vertices - rest
        assert np.abs(moved[:, 1] - 0.1).min() < 1e-5  # most vertices just translated
        assert np.abs(moved - [0, 0.1, 0]).max() > 0.05   # the forearm turned
        transforms = body.joint_transforms
        assert transforms.shape == (53, 4, 4)
        np.testing.assert_allclose(transforms[:, 3], np.tile([0, 0, 0, 1], (53, 1)), atol=1e-6)
        body.set_pose()  # back to rest
        np.testing.assert_allclose(body.vertices, rest, atol=1e-5)


def test_arrays_equal_the_library_bit_for_bit(model, tmp_path):
    with sscape.Body(model) as body:
        body.shape = model.sample_shapes(1, seed=3)[0]
        path = tmp_path / "body.ply"
        body.write(path)
        np.testing.assert_array_equal(read_ply_vertices(path), body.vertices)


def test_sliders_measurements_and_files(model, tmp_path):
    names = sscape.measurement_names()
    assert "stature" in names and "waist_girth" in names
    with sscape.Body(model) as body:
        body.set_slider("stature", 1.80)
        assert abs(body.sliders["stature"] - 1.80) < 1e-3
        m = body.measure()
        assert list(m) == names
        assert abs(m["stature"] - 1.80) < 0.01
        with pytest.raises(KeyError, match="no slider 'height'"):
            body.set_slider("height", 1.8)
        with pytest.raises(sscape.SscapeError) as e:
            body.set_slider("stature", 9.0)
        assert e.value.status == -1 and "range" in str(e.value)
        for ext in ("obj", "ply", "glb"):
            body.write(tmp_path / f"b.{ext}")
            assert (tmp_path / f"b.{ext}").stat().st_size > 100000
        with pytest.raises(ValueError):
            body.write(tmp_path / "b.obj", format="stl")
        with pytest.raises(sscape.SscapeError) as e:
            body.write(tmp_path / "b.stl")
        assert e.value.status_name == "SSC_ERROR_INVALID_ARGUMENT"
        assert not (tmp_path / "b.stl").exists()


def test_errors_carry_status_and_message(model, tmp_path):
    with sscape.Body(model) as body:
        with pytest.raises(sscape.SscapeError) as e:
            body.shape = [np.nan]
        assert e.value.status == -1 and "is nan" in str(e.value)
        with pytest.raises(sscape.SscapeError):
            body.shape = np.ones(51)  # more than the model has
        with pytest.raises(ValueError, match="shape"):
            body.set_pose(np.zeros((52, 4)))
        with pytest.raises(sscape.SscapeError) as e:
            body.set_pose(np.zeros((53, 4)))  # zero quaternions
        assert e.value.status_name == "SSC_ERROR_INVALID_ARGUMENT"
        with pytest.raises(KeyError, match="no segment 'tail'"):
            body.set_segment_shape("tail", [1.0])
        # A segment's coefficients move that segment only (the default model has segment spaces).
        before = body.vertices.copy()
        body.set_segment_shape("arm_l", [2.0])
        assert body.segment_shape("arm_l")[0] == 2.0 and not body.segment_shape("arm_l")[1:].any()
        moved = np.linalg.norm(body.vertices - before, axis=1)
        assert moved[before[:, 0] > 0.3].max() > 0.005 and moved[before[:, 0] < -0.3].max() == 0  # +X: the left
    with pytest.raises(ValueError, match="closed"):
        body.vertices
    with pytest.raises(sscape.SscapeError) as e:
        sscape.Model.from_file(tmp_path / "missing.sscape")
    assert e.value.status_name == "SSC_ERROR_IO"
    with pytest.raises(sscape.SscapeError) as e:
        sscape.Model.from_bytes(b"not a model file, " * 10)
    assert e.value.status_name == "SSC_ERROR_MODEL_CORRUPT"


def test_models_from_files_and_bytes(model, tmp_path):
    shapes = model.sample_shapes(4, seed=7)
    assert shapes.shape == (4, 50) and shapes.dtype == np.float32
    np.testing.assert_array_equal(shapes, model.sample_shapes(4, seed=7))
    assert np.abs(shapes).max() <= 2.5
    # A body from a model loaded twice over: the same vertices.
    source = os.environ.get("SSCAPE_SOURCE_DIR") or pathlib.Path(__file__).resolve().parents[3]
    default_file = pathlib.Path(source) / "model_format" / "models" / "sscape-default.sscape"
    for other in (sscape.Model.from_file(default_file), sscape.Model.from_bytes(default_file.read_bytes())):
        with other, sscape.Body(other) as a, sscape.Body(model) as b:
            a.shape = b.shape = shapes[0]
            np.testing.assert_array_equal(a.vertices, b.vertices)


def test_batch_synthesis_equals_bodies(model):
    shapes = model.sample_shapes(3, seed=11)
    poses = np.tile(np.array([0, 0, 0, 1], np.float32), (3, 53, 1))
    poses[1, model.joint_names.index("lowerarm_r")] = [0, np.sin(0.3), 0, np.cos(0.3)]
    translations = np.array([[0, 0, 0], [0.5, 0, 0], [0, 0.2, -1]], np.float32)
    vertices, normals = model.synthesize(shapes, poses, translations, normals=True)
    assert vertices.shape == normals.shape == (3, 13380, 3) and vertices.dtype == np.float32
    for i in range(3):
        with sscape.Body(model) as body:
            body.shape = shapes[i]
            body.set_pose(poses[i], translations[i])
            np.testing.assert_array_equal(vertices[i], body.vertices)
            np.testing.assert_array_equal(normals[i], body.normals)
    mean = model.synthesize(count=2)
    np.testing.assert_array_equal(mean[0], mean[1])
    with pytest.raises(ValueError, match="disagree"):
        model.synthesize(shapes, translations=translations[:2])
    with pytest.raises(ValueError, match="poses has shape"):
        model.synthesize(poses=np.zeros((2, 52, 4)))
    with pytest.raises(sscape.SscapeError):
        model.synthesize(shapes=np.full((1, 3), np.inf))


def test_fitter_reports_each_frame_and_leaves_a_failed_one_out(model):
    # Two frames of one person and, between them, a cloud that is no person (a ball): that frame
    # fails and is reported, the others are fitted with the shared shape.
    shape = model.sample_shapes(1, seed=9)[0]
    surfaces = []
    for angle in (0.0, 0.5):
        with sscape.Body(model) as body:
            body.shape = shape
            q = np.tile(np.array([0, 0, 0, 1], np.float32), (53, 1))
            q[model.joint_names.index("upperarm_l")] = [0, 0, np.sin(-angle / 2), np.cos(-angle / 2)]
            body.set_pose(q)
            surfaces.append(body.vertices)
    rng = np.random.default_rng(3)
    ball = rng.normal(size=(3000, 3))
    ball = (0.3 * ball / np.linalg.norm(ball, axis=1, keepdims=True) + [0, 1.0, 0]).astype(np.float32)
    seen = []
    with sscape.Fitter(model, max_points=1500) as fitter:
        fitter.add_points(surfaces[0][::3])
        fitter.add_points(ball, frame=fitter.frame_count)
        fitter.add_points(surfaces[1][::3], frame=fitter.frame_count)
        report = fitter.solve(frame_done=lambda f, r: seen.append((f, r["failed"])) and False)
        assert report["failed_frames"] == 1 and report["implausible"] is True
        assert report["problem"] != "none"
        failed = fitter.frame_report(1)
        assert failed["failed"] is True and failed["left_out"] is True and failed["problem_text"], failed
        for f in (0, 2):
            good = fitter.frame_report(f)
            assert good["failed"] is False and good["problem"] == "none" and good["problem_text"] == "", good
            error = np.linalg.norm(fitter.vertices(f) - surfaces[f // 2], axis=1).mean()
            assert error < 0.006, f"frame {f}: mean vertex error {error * 1000:.2f} mm"
        assert sorted(set(f for f, _ in seen)) == [0, 1, 2] and (1, True) in seen
        with pytest.raises(sscape.SscapeError):
            fitter.frame_report(3)


def test_fitter_recovers_a_body_from_its_surface(model):
    with sscape.Body(model) as body:
        body.shape = model.sample_shapes(1, seed=5)[0]
        q = np.tile(np.array([0, 0, 0, 1], np.float32), (53, 1))
        q[model.joint_names.index("upperarm_l")] = [0, 0, np.sin(-0.2), np.cos(-0.2)]
        body.set_pose(q, translation=[0.3, 0, -0.2])
        truth = body.vertices
        names = model.landmark_names[:10]
        landmarks = body.landmarks[:10]
    iterations = []
    with sscape.Fitter(model, max_points=2000) as fitter:
        fitter.add_points(truth[::4])
        fitter.add_landmarks(names, landmarks)
        report = fitter.solve(lambda i, cost: iterations.append(cost) and False)
        assert report["converged"] is True and report["implausible"] is False and report["iterations"] == len(iterations) > 0
        error = np.linalg.norm(fitter.vertices() - truth, axis=1).mean()
        assert error < 0.005, f"mean vertex error {error * 1000:.2f} mm"
        rotations, translation, scale = fitter.pose()
        assert rotations.shape == (53, 4) and scale == 1.0
        np.testing.assert_allclose(translation, [0.3, 0, -0.2], atol=0.02)
        residuals = fitter.point_residuals()
        assert residuals.shape == (truth[::4].shape[0],) and np.median(residuals) < 0.003
        assert fitter.shape.shape == (50,)
        # Segment coefficients by name or index, standard deviations.
        for s in model.segments:
            c = fitter.segment_shape(s.name)
            assert c.shape == (s.shape_count,) and np.all(np.isfinite(c)) and np.all(np.abs(c) < 10)
        with pytest.raises(KeyError):
            fitter.segment_shape("tail")
    with sscape.Fitter(model, fit_segments=0) as fitter:  # the whole body's components alone
        fitter.add_points(truth[::4])
        fitter.solve()
        assert all(np.all(fitter.segment_shape(i) == 0) for i in range(len(model.segments)))
    with sscape.Fitter(model) as fitter:
        fitter.add_points(truth[::4])
        with pytest.raises(sscape.SscapeError) as e:
            fitter.solve(lambda i, cost: True)  # cancelled at once
        assert e.value.status_name == "SSC_ERROR_CANCELLED"
        def broken(i, cost):
            raise RuntimeError("from the callback")
        with pytest.raises(RuntimeError, match="from the callback"):
            fitter.solve(broken)
        with pytest.raises(sscape.SscapeError) as e:
            fitter.add_landmarks(["Nowhere"], [[0, 0, 0]])
        assert e.value.status_name == "SSC_ERROR_NOT_FOUND"
        with pytest.raises(sscape.SscapeError, match="twice"):  # one landmark at two places
            fitter.add_landmarks([names[0], names[0]], landmarks[:2])
        fitter.add_landmarks(names[:1], landmarks[:1])
        with pytest.raises(sscape.SscapeError, match="twice"):  # already in the frame
            fitter.add_landmarks(names[:1], landmarks[:1])
    with pytest.raises(TypeError, match="unknown fitter options: sigma"):
        sscape.Fitter(model, sigma=1)


def test_lookups_by_name_one_measurement_and_landmarks_by_index(model):
    assert model.index("joint", "upperarm_l") == model.joint_names.index("upperarm_l")
    assert model.index("landmark", model.landmark_names[5]) == 5
    assert model.index("slider", "stature") == [s.name for s in model.sliders].index("stature")
    for kind in ("joint", "landmark", "slider", "segment"):
        with pytest.raises(KeyError):
            model.index(kind, "nothing")
    with pytest.raises(ValueError):
        model.index("bone", "x")
    with sscape.Body(model) as body:
        body.shape = [1.0]
        assert body.measure_one("stature") == body.measure()["stature"]
        with pytest.raises(sscape.SscapeError):
            body.measure_one("wingspan")
        landmarks = body.landmarks
    with sscape.Fitter(model) as by_index, sscape.Fitter(model) as by_name:
        by_index.add_landmark_indices(np.arange(20), landmarks[:20])
        by_name.add_landmarks(model.landmark_names[:20], landmarks[:20])
        assert by_index.solve()["landmark_rms"] == by_name.solve()["landmark_rms"]
        assert np.array_equal(by_index.shape, by_name.shape)
        with pytest.raises(ValueError):
            by_index.add_landmark_indices([0, 1], landmarks[:3])


def test_fitter_takes_depth_images(model):
    # A wall 2 m in front of a 64 x 48 camera: every pixel but the rim (its 5 x 5 neighbourhood) is usable.
    depth_m = np.full((48, 64), 2.0, np.float32)
    with sscape.Fitter(model) as fitter:
        added = fitter.add_depth_image(depth_m, 60, 60, 31.5, 23.5)
        assert 44 * 60 <= added <= 48 * 64
        # The same image in millimetres, and with half of it masked out.
        assert fitter.add_depth_image((depth_m * 1000).astype(np.uint16), 60, 60, 31.5, 23.5, frame=0) == added
        mask = np.ones(depth_m.shape, bool)
        mask[:, 32:] = False
        assert fitter.add_depth_image(depth_m, 60, 60, 31.5, 23.5, mask=mask, frame=0) < added * 0.6
        # Beyond the depth limit nothing is usable; a camera pose must be rigid.
        with pytest.raises(sscape.SscapeError):
            fitter.add_depth_image(depth_m, 60, 60, 31.5, 23.5, max_depth=1.5, frame=0)
        with pytest.raises(sscape.SscapeError):
            fitter.add_depth_image(depth_m, 60, 60, 31.5, 23.5, camera_to_world=np.diag([2, 1, 1, 1]), frame=0)
        with pytest.raises(sscape.SscapeError):
            fitter.add_depth_image(depth_m, -1, 60, 31.5, 23.5, frame=0)
        with pytest.raises(TypeError):
            fitter.add_depth_image(depth_m.astype(np.int32), 60, 60, 31.5, 23.5)
        # A rigid camera pose (moved 1 m along x) is taken; the C++ tests check where its points land.
        pose = np.eye(4, dtype=np.float32)
        pose[0, 3] = 1.0
        assert fitter.add_depth_image(depth_m, 60, 60, 31.5, 23.5, camera_to_world=pose) == added
        assert fitter.frame_count == 1


def test_registration_brings_the_template_onto_a_scan(model):
    # A "scan": a body's surface with a hole, points only.
    with sscape.Body(model) as body:
        body.shape = model.sample_shapes(1, seed=8)[0]
        truth = body.vertices
    keep = truth[:, 1] < 1.2  # no head and shoulders above 1.2 m: filled in from the model
    stages = []
    with sscape.Registration(model, max_iterations=2) as reg:
        with pytest.raises(sscape.SscapeError):
            reg.run()  # no scan yet
        reg.set_scan(truth[keep])
        report = reg.run(lambda stage, done, total: stages.append(stage) and False)
        assert {"fit", "deform"} <= set(stages)
        assert report["valid_vertices"] > 0.5 * model.vertex_count
        assert set(report["regions"]) >= {"head", "torso", "legs"}
        v = reg.vertices()
        error = np.linalg.norm(v[keep] - truth[keep], axis=1).mean()
        assert error < 0.01, f"mean error on the scanned part {error * 1000:.1f} mm"
        valid = reg.valid()
        assert valid.dtype == bool and valid[keep].mean() > valid[~keep].mean()
        d = reg.vertex_distances()
        assert d.shape == (model.vertex_count,) and (d[valid] >= 0).all()
        shape, rotations, translation, scale = reg.fit()
        assert shape.shape == (50,) and rotations.shape == (53, 4)
        # The fit's segment shapes (the default model has six): the default fit uses them, but the head's.
        arms = [reg.fit_segment_shape("arm_l"), reg.fit_segment_shape(2)]
        assert all(a.shape == (10,) for a in arms) and any((a != 0).any() for a in arms)
        assert (reg.fit_segment_shape("head") == 0).all()
        with pytest.raises(sscape.SscapeError):
            reg.fit_segment_shape(6)
        with pytest.raises(sscape.SscapeError) as e:
            reg.set_landmarks(["Nowhere"], [[0, 0, 0]])
        assert e.value.status_name == "SSC_ERROR_NOT_FOUND"
        with pytest.raises(sscape.SscapeError, match="twice") as e:  # two positions for one point
            reg.set_landmarks(["Sellion", "Sellion"], [[0, 1.6, 0.1], [0, 1.3, 0.1]])
        assert e.value.status_name == "SSC_ERROR_INVALID_ARGUMENT"
    with pytest.raises(ValueError, match="start must be one of"):
        sscape.Registration(model, start="magic")


def test_made_to_measure(model):
    with sscape.Body(model) as body:
        assert body.make_to_measure({"stature": 1.72, "waist_girth": 0.86}, sex=1, age=40)
        m = body.measure()
        assert abs(m["stature"] - 1.72) < 0.001 and abs(m["waist_girth"] - 0.86) < 0.001
        with pytest.raises(sscape.SscapeError) as e:
            body.make_to_measure({"wingspan": 1.8})
        assert e.value.status_name == "SSC_ERROR_NOT_FOUND"
        with pytest.raises(sscape.SscapeError) as e:
            body.make_to_measure({"stature": 4.5})
        assert e.value.status == -1 and "range" in str(e.value)
        with pytest.raises(ValueError):
            body.make_to_measure({})


def test_every_declared_function_is_in_the_header():
    """The declarations are the C API's: a renamed or removed function fails here, not at a user's call."""
    import re
    from sscape import _native
    source = os.environ.get("SSCAPE_SOURCE_DIR") or pathlib.Path(__file__).resolve().parents[3]
    header = (pathlib.Path(source) / "include" / "sscape" / "sscape.h").read_text()
    exported = set(re.findall(r"^SSC_(?:API|EXPERIMENTAL)\s[^;(]*?\b(ssc_\w+)\s*\(", header, re.M))
    assert len(exported) > 100
    declared = set(_native._DECLARATIONS)
    assert declared == exported, sorted(declared ^ exported)  # every function of the header, declared
    offline = (pathlib.Path(source) / "include" / "sscape" / "sscape_offline.h").read_text()
    exported_offline = set(re.findall(r"^SSC_(?:API|EXPERIMENTAL)\s[^;(]*?\b(ssc_\w+)\s*\(", offline, re.M))
    assert set(_native._OFFLINE_DECLARATIONS) == exported_offline, sorted(set(_native._OFFLINE_DECLARATIONS) ^ exported_offline)


def test_axis_angle_poses_landmarks_joint_limits_and_sliders(model):
    # An axis-angle pose is the quaternion pose the library converts it to, to the bit.
    J = model.joint_count
    rng = np.random.default_rng(4)
    aa = (rng.normal(size=(J, 3)) * 0.2).astype(np.float32)
    q = np.stack([sscape.quaternion_from_axis_angle(v) for v in aa])
    assert q.dtype == np.float32 and np.allclose(np.linalg.norm(q, axis=1), 1, atol=1e-6)
    half = np.linalg.norm(aa[0]) / 2
    assert np.isclose(q[0, 3], np.cos(half), atol=1e-6)
    with sscape.Body(model) as a, sscape.Body(model) as b:
        a.set_pose_axis_angle(aa, translation=[0.1, 0, 0])
        b.set_pose(q, translation=[0.1, 0, 0])
        assert np.array_equal(a.vertices, b.vertices)
        with pytest.raises(ValueError):
            a.set_pose_axis_angle(aa[:, :2])
        with pytest.raises(sscape.SscapeError):
            sscape.quaternion_from_axis_angle([np.nan, 0, 0])
        # The rest landmarks are the mean body's.
        rest = model.landmark_positions
        assert rest.shape == (model.landmark_count, 3) and rest.dtype == np.float32
        with sscape.Body(model) as mean:
            assert np.allclose(mean.landmarks, rest, atol=1e-6)
        # All sliders at once: the same body as one at a time from the population's typical body.
        values = {s.name: s.mean for s in model.sliders}
        values["stature"] = 1.80
        a.set_sliders(values)
        assert abs(a.sliders["stature"] - 1.80) < 1e-3
        with pytest.raises(KeyError):
            a.set_sliders({"stature": 1.8})
    limits = model.joint_limits()
    assert set(limits) == set(model.joint_names)
    limited = [v for v in limits.values() if v is not None]
    assert limited and any(v is None for v in limits.values())  # the root has none
    for v in limited:
        assert v["frame"].shape == (3, 3) and np.all(v["lower"] <= v["upper"])
        assert np.allclose(v["frame"] @ v["frame"].T, np.eye(3), atol=1e-5)
    # The default model's segment shape spaces: six, each a band-blended part of the body.
    assert [seg.name for seg in model.segments] == ["head", "arm_l", "arm_r", "torso", "leg_l", "leg_r"]
    vertices, weights = model.segment_vertices("head")
    assert vertices.dtype == np.uint32 and np.all(vertices < model.vertex_count)
    assert np.all((weights > 0) & (weights <= 1)) and np.any(weights < 1)
    with pytest.raises(KeyError):
        model.segment_vertices("tail")


def test_topology_skin_poses_and_matrices(model):
    quads = model.quads
    assert quads.shape == (13378, 4) and quads.dtype == np.uint32
    uv, tri_uv = model.uvs
    assert uv.shape[1] == 2 and tri_uv.shape == (model.triangle_count, 3) and tri_uv.max() < uv.shape[0]
    sets = model.vertex_sets
    assert set(sets) == {"head", "torso", "arms", "hands", "legs", "feet"}
    assert sum(len(v) for v in sets.values()) == model.vertex_count
    joints, weights = model.skin
    assert joints.dtype == np.uint16 and joints.max() < 53
    np.testing.assert_allclose(weights.sum(axis=1), 1, atol=1e-5)
    poses = sscape.named_poses()
    assert "t_pose" in poses and poses["t_pose"]
    t = model.named_pose("t_pose")
    fists = model.named_pose("t_pose", left_hand=1, right_hand=1)
    assert t.shape == (53, 4) and not np.array_equal(t, fists)
    with pytest.raises(sscape.SscapeError) as e:
        model.named_pose("moonwalk")
    assert e.value.status_name == "SSC_ERROR_NOT_FOUND"
    with sscape.Body(model) as body:
        body.set_pose(t)
        skinning = body.skinning_matrices
        np.testing.assert_allclose(skinning, body.joint_transforms @ body.inverse_bind_matrices, atol=1e-5)
        # An elbow bent backwards beyond its range: clamped, or refused.
        q = np.tile(np.array([0, 0, 0, 1], np.float32), (53, 1))
        q[model.joint_names.index("lowerarm_l")] = [np.sin(-1.2), 0, 0, np.cos(-1.2)]
        q[model.joint_names.index("lowerarm_r")] = [0, np.sin(-1.2), 0, np.cos(-1.2)]
        with pytest.raises(sscape.SscapeError):
            body.set_pose_limited(q, clamp=False)
        assert body.set_pose_limited(q) >= 1


def test_context_with_one_worker_gives_the_same_bodies(model):
    context = sscape.Context(worker_count=1)
    single = sscape.Model(context)
    shapes = model.sample_shapes(4, seed=2)
    np.testing.assert_array_equal(single.synthesize(shapes), model.synthesize(shapes))
    context.close()  # the model keeps it alive
    assert single.synthesize(count=1).shape == (1, 13380, 3)


def test_the_library_warnings_reach_the_sscape_logger(model, tmp_path, caplog):
    # A misspelt landmark name was once dropped without a word for Python users: the CLI showed the
    # library's warning, the default Python context had no log sink.
    if not sscape._native.has_offline:
        pytest.skip("file inputs need libsscape_offline")
    lnd = tmp_path / "three.lnd"
    lnd.write_text("AUX =\n"
                   "  1   0    1     0.00   -15.73  1604.05    33.32 Sellion\n"
                   "  2   0    2     0.00   -82.05  1602.28   -52.91 Rt. Tragion\n"
                   "  3   0    3     0.00    62.13  1598.11   -49.82 Lt. Tragoin\n"
                   "  4   0    4     0.00    62.13  1598.11   -49.82 Lt. Tragion\n"
                   "END =\n")
    fitter = sscape.Fitter(model)
    with caplog.at_level(logging.WARNING, logger="sscape"):
        info = fitter.add_landmarks_file(lnd)
    assert info["unknown"] == 1, info
    said = [r.getMessage() for r in caplog.records if r.name == "sscape"]
    assert any("landmark 'Lt. Tragoin' is not one of the model's; ignored" in m for m in said), said
    assert all(r.levelno == logging.WARNING for r in caplog.records if r.name == "sscape")


def test_levels_of_detail(model, tmp_path):
    """Every level of the default model: its rest vertices are its sources' weighted sums of the
    body's, its posed vertices come from its own skin, and it is written with its own triangles."""
    levels = model.levels
    assert [lv.name for lv in levels] == ["full", "simplified", "female1605", "proxy741"]
    assert levels[0].vertex_count == model.vertex_count and levels[3].vertex_count == 741
    body = sscape.Body(model)
    body.shape = model.sample_shapes(1, seed=3)[0]
    body.set_pose(model.named_pose("sitting"))
    rest = body.rest_vertices
    for lv in levels:
        vertices, weights = model.level_sources(lv.name)
        assert np.allclose(np.einsum("nk,nkc->nc", weights, rest[vertices]), body.level_rest_vertices(lv.index), atol=1e-5)
        joints, skin = model.level_skin(lv.index)
        assert joints.shape == (lv.vertex_count, 4) and np.allclose(skin.sum(axis=1), 1, atol=1e-3)
        posed = body.level_vertices(lv.name)
        assert posed.shape == (lv.vertex_count, 3) and np.isfinite(posed).all()
        assert np.allclose(np.linalg.norm(body.level_normals(lv.index), axis=1), 1, atol=1e-3)
        assert model.level_triangles(lv.index).max() < lv.vertex_count
        uv, tri = model.level_uvs(lv.index)
        assert tri.shape == (lv.triangle_count, 3) and tri.max() < uv.shape[0]
    assert np.array_equal(body.level_vertices(0), body.vertices)
    path = tmp_path / "far.obj"
    body.write(path, level="proxy741")
    text = path.read_text()
    assert text.count("\nv ") == 741 and text.count("\nf ") == levels[3].triangle_count
    body.write(tmp_path / "all.glb", level="all")
    assert (tmp_path / "all.glb").stat().st_size > 1_000_000
    with pytest.raises(sscape.SscapeError):
        body.write(tmp_path / "all.obj", level="all")
    assert not (tmp_path / "all.obj").exists()
    with pytest.raises(KeyError, match="proxy741"):
        model.level("proxy9")
    with pytest.raises(IndexError):
        body.level_vertices(4)
    # Many bodies of a level at once: what a Body gives.
    shapes = model.sample_shapes(3, seed=2)
    batch, batch_normals = model.synthesize(shapes=shapes, normals=True, level="proxy741")
    assert batch.shape == (3, 741, 3) and batch_normals.shape == (3, 741, 3)
    body.shape = shapes[2]
    body.set_pose()
    assert np.abs(batch[2] - body.level_vertices("proxy741")).max() < 1e-6


def _glb_json(path):
    import json
    import struct
    data = path.read_bytes()
    length = struct.unpack_from("<I", data, 12)[0]
    return json.loads(data[20:20 + length])


def test_default_model_bytes(tmp_path):
    data = sscape.default_model_bytes()
    assert data[:8] == b"\x89SSCAPE\n" and len(data) <= 2_500_000
    (tmp_path / "default.sscape").write_bytes(data)
    assert sscape.Model.from_file(tmp_path / "default.sscape").vertex_count == 13380


def test_glb_morph_targets(model, tmp_path):
    body = sscape.Body(model)
    body.write(tmp_path / "components.glb", level="all", morphs=4)
    doc = _glb_json(tmp_path / "components.glb")
    assert len(doc["meshes"]) == len(model.levels)
    for mesh in doc["meshes"]:
        assert mesh["extras"]["targetNames"] == ["component_1", "component_2", "component_3", "component_4"]
        assert len(mesh["primitives"][0]["targets"]) == 4
        assert "_MODEL_VERTEX" in mesh["primitives"][0]["attributes"]
    morphs = doc["skins"][0]["extras"]["sscape_morphs"]
    assert [m["unit"] for m in morphs] == ["sd"] * 4
    assert len(morphs[0]["node_translation"]) == 3 * len(model.joint_names)
    body.write(tmp_path / "sliders.glb", morphs="sliders")
    names = _glb_json(tmp_path / "sliders.glb")["meshes"][0]["extras"]["targetNames"]
    assert names == [s.name for s in model.sliders]
    with pytest.raises(sscape.SscapeError, match="glTF"):
        body.write(tmp_path / "x.obj", morphs=2)
    with pytest.raises(TypeError):
        body.write(tmp_path / "x.glb", morphs=2.5)
    with pytest.raises(sscape.SscapeError):
        body.write(tmp_path / "x.glb", morphs=model.shape_count + 1)
    assert not (tmp_path / "x.obj").exists() and not (tmp_path / "x.glb").exists()
