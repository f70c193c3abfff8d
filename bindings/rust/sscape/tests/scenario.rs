//! The safe crate against the library: the bindings' common scenario equal to the C program's bytes
//! (SSCAPE_SCENARIO_REFERENCE; skipped with a message without it), errors, lifetimes, threads.
#![allow(clippy::excessive_precision)] // the digits of tests/bindings/scenario.c, as written there
use sscape::{sys, Model};

fn bytes(parts: &[&[f32]]) -> Vec<u8> {
    parts.iter().flat_map(|p| p.iter().flat_map(|v| v.to_ne_bytes())).collect()
}

/// tests/bindings/scenario.c, step for step.
fn scenario() -> sscape::Result<Vec<u8>> {
    let model = Model::load_default()?;
    let mut body = model.body()?;
    body.set_shape(&[0.8, -0.5, 1.2, 0.3, -1.0])?;
    let mut rotations = vec![0f32; model.joint_count() * 4];
    for j in 0..model.joint_count() {
        rotations[j * 4 + 3] = 1.0;
    }
    let arm = model.joint_index("upperarm_l")? * 4;
    rotations[arm..arm + 4].copy_from_slice(&[0.0, 0.0, 0.258_819_04, 0.965_925_83]);
    let elbow = model.joint_index("lowerarm_r")? * 4;
    rotations[elbow..elbow + 4].copy_from_slice(&[0.0, -0.173_648_18, 0.0, 0.984_807_75]);
    body.set_pose(Some(&rotations), Some([0.1, 0.0, -0.2]))?;
    let vertices = body.vertices()?;
    let measurements = body.measure()?;
    let landmarks = body.landmarks()?;
    let mut fitter = model.fitter(None)?;
    fitter.add_landmarks_by_name(0, &model.landmark_names()?, &landmarks, None)?;
    fitter.solve()?;
    let pose = fitter.pose(0)?;
    let batch = model.synthesize(&model.sample_shapes(7, 3, 2.0)?, None, None)?;
    Ok(bytes(&[&vertices, &measurements, &landmarks, &fitter.shape()?, &pose.rotations, &pose.translation,
               &[pose.scale], &batch]))
}

#[test]
fn scenario_gives_the_c_apis_bytes() {
    let path = match std::env::var("SSCAPE_SCENARIO_REFERENCE") {
        Ok(path) => path,
        Err(_) => {
            eprintln!("skipped: SSCAPE_SCENARIO_REFERENCE not set (tests/bindings/run.sh sets it)");
            return;
        }
    };
    let theirs = std::fs::read(path).expect("the reference file");
    let mine = scenario().expect("the scenario");
    assert_eq!(mine.len(), theirs.len());
    assert!(mine == theirs, "the floats differ from the C program's");
}

#[test]
fn library_abi_major_is_the_crates() {
    assert_eq!(sscape::version().0, sscape::ABI_MAJOR);
    assert_eq!(unsafe { sys::ssc_version() }, sys::SSC_VERSION_NUMBER - sys::SSC_VERSION_PATCH + sscape::version().2);
}

#[test]
fn errors_carry_the_status_and_message() {
    let model = Model::load_default().unwrap();
    let e = model.joint_index("no_such_joint").unwrap_err();
    assert_eq!(e.status, sys::SSC_ERROR_NOT_FOUND);
    assert_eq!(e.code(), "SSC_ERROR_NOT_FOUND");
    assert!(e.message.contains("no_such_joint"), "{}", e);
    let mut body = model.body().unwrap();
    assert_eq!(body.set_shape(&[f32::NAN]).unwrap_err().status, sys::SSC_ERROR_INVALID_ARGUMENT);
    assert_eq!(body.set_pose(Some(&[0.0; 4]), None).unwrap_err().status, sys::SSC_ERROR_INVALID_ARGUMENT);
    let mut fitter = model.fitter(None).unwrap();
    let e = fitter.add_landmarks_by_name(0, &["Sellion", "Nonsense"], &[0.0; 6], None).unwrap_err();
    assert!(e.status == sys::SSC_ERROR_NOT_FOUND && e.message.contains("Nonsense"), "{}", e);
    let mut def = Model::fitter_def();
    def.shape_count = 1_000_000;
    assert_eq!(model.fitter(Some(&def)).err().unwrap().status, sys::SSC_ERROR_INVALID_ARGUMENT);
    let dir = std::env::temp_dir().join(format!("sscape-rust-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("corrupt.sscape"), b"SSCAPE not really a model").unwrap();
    assert!(Model::load(dir.join("corrupt.sscape")).is_err());
    assert_eq!(Model::load(dir.join("missing.sscape")).err().unwrap().status, sys::SSC_ERROR_IO);
    assert!(Model::from_bytes(&[0u8; 16]).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn levels_of_detail_are_listed_posed_and_written() {
    let model = Model::load_default().unwrap();
    let levels = model.levels().unwrap();
    let names: Vec<&str> = levels.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["full", "simplified", "female1605", "proxy741"]);
    assert_eq!(levels[3].vertex_count, 741);
    let tris = model.level_triangles(3).unwrap();
    assert!(tris.len() == levels[3].triangle_count * 3 && tris.iter().all(|&v| v < 741));
    let mut body = model.body().unwrap();
    let far = body.level_vertices(3).unwrap();
    assert!(far.len() == 741 * 3 && far.iter().all(|x| x.is_finite()));
    assert_eq!(body.level_vertices(0).unwrap(), body.vertices().unwrap());
    assert!(body.level_vertices(4).is_err());
    let dir = std::env::temp_dir().join(format!("sscape-rs-levels-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    body.write_level(dir.join("all.glb"), sscape::ALL_LEVELS).unwrap();
    assert!(std::fs::metadata(dir.join("all.glb")).unwrap().len() > 1_000_000);
    assert!(body.write_level(dir.join("all.obj"), sscape::ALL_LEVELS).is_err());
    body.write_with_morphs(dir.join("morphs.glb"), sscape::ALL_LEVELS, sscape::Morphs::Components(4)).unwrap();
    body.write_with_morphs(dir.join("sliders.glb"), 0, sscape::Morphs::Sliders).unwrap();
    let glb = std::fs::read(dir.join("morphs.glb")).unwrap();
    let json_length = u32::from_le_bytes([glb[12], glb[13], glb[14], glb[15]]) as usize;
    let text = String::from_utf8_lossy(&glb[20..20 + json_length]);
    assert!(text.contains("\"component_4\"") && text.contains("sscape_morphs"));
    assert!(body.write_with_morphs(dir.join("x.obj"), 0, sscape::Morphs::Components(2)).is_err());
    assert!(body.write_with_morphs(dir.join("x.glb"), 0, sscape::Morphs::Components(51)).is_err());
    // Many bodies of a level at once: what a body gives.
    let shapes = model.sample_shapes(3, 2, 2.5).unwrap();
    let batch = model.synthesize_level(3, &shapes, None, None).unwrap();
    assert_eq!(batch.len(), 2 * 741 * 3);
    body.set_shape(&shapes[model.shape_count()..]).unwrap();
    body.set_pose(None, None).unwrap();
    let one = body.level_vertices(3).unwrap();
    assert!(one.iter().zip(&batch[741 * 3..]).all(|(a, b)| (a - b).abs() < 1e-6));
    assert!(model.synthesize_level(4, &shapes, None, None).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn segment_shape_spaces_move_their_part_only() {
    let model = Model::load_default().unwrap();
    let segments = model.segments().unwrap();
    let names: Vec<&str> = segments.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["head", "arm_l", "arm_r", "torso", "leg_l", "leg_r"]);
    let arm = model.segment_index("arm_l").unwrap();
    assert!(segments[arm].shape_count == 10 && segments[arm].vertex_count > 1000, "{:?}", segments[arm]);
    let mut body = model.body().unwrap();
    let before = body.vertices().unwrap();
    body.set_segment_shape(arm, &[2.0]).unwrap();
    let shape = body.segment_shape(arm, segments[arm].shape_count).unwrap();
    assert!(shape[0] == 2.0 && shape[1..].iter().all(|&c| c == 0.0), "{:?}", shape);
    let after = body.vertices().unwrap();
    let (mut left, mut right) = (0f32, 0f32);
    for (b, a) in before.chunks(3).zip(after.chunks(3)) {
        let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
        if b[0] > 0.3 {
            left = left.max(d); // +X: the body's left
        }
        if b[0] < -0.3 {
            right = right.max(d);
        }
    }
    assert!(left > 0.005 && right == 0.0, "the left arm moves {} m, the right {} m", left, right);
    assert_eq!(model.segment_index("tail").unwrap_err().status, sys::SSC_ERROR_NOT_FOUND);
    assert_eq!(body.set_segment_shape(arm, &[0.0; 11]).unwrap_err().status, sys::SSC_ERROR_INVALID_ARGUMENT);
    assert_eq!(body.set_segment_shape(6, &[1.0]).unwrap_err().status, sys::SSC_ERROR_INVALID_ARGUMENT);
}

#[test]
fn bodies_outlive_their_model_value_and_fits_recover_shapes() {
    let mut body = {
        let model = Model::load_default().unwrap();
        model.body().unwrap()
    };  // the Model value is dropped; the body holds the C model
    body.set_shape(&[1.5, -1.0]).unwrap();
    let stature = body.measure_by_name("stature").unwrap();
    assert!(stature > 1.4 && stature < 2.1, "stature {}", stature);
    assert_eq!(body.measure().unwrap().len(), sscape::measurements().unwrap().len());
    let model = Model::load_default().unwrap();
    let mut fitter = model.fitter(None).unwrap();
    fitter.add_landmarks_by_name(0, &model.landmark_names().unwrap(), &body.landmarks().unwrap(), None).unwrap();
    let report = fitter.solve_with_progress(|_, _| false).unwrap();
    assert!(report.iterations > 0 && report.landmark_rms < 0.01, "{:?}", report);
    let mut calls = 0;
    let e = fitter.solve_with_progress(|_, _| { calls += 1; calls >= 2 }).unwrap_err();
    assert_eq!(e.status, sys::SSC_ERROR_CANCELLED);
    assert_eq!(calls, 2);
    let e = fitter.solve_with_progress(|_, _| panic!("a callback's panic cancels the solve")).unwrap_err();
    assert_eq!(e.status, sys::SSC_ERROR_CANCELLED);
}

#[test]
fn one_model_many_threads() {
    let model = Model::load_default().unwrap();
    let shapes = model.sample_shapes(3, 4, 2.5).unwrap();
    let batch = model.synthesize(&shapes, None, None).unwrap();
    let (k, v) = (model.shape_count(), model.vertex_count() * 3);
    std::thread::scope(|scope| {
        for b in 0..4 {
            let (model, shapes, batch) = (&model, &shapes, &batch);
            scope.spawn(move || {
                let mut body = model.body().unwrap();
                body.set_shape(&shapes[b * k..(b + 1) * k]).unwrap();
                assert!(body.vertices().unwrap() == batch[b * v..(b + 1) * v]);
            });
        }
    });
    // A body moves to another thread (Send).
    let mut body = model.body().unwrap();
    let handle = std::thread::spawn(move || body.vertices().unwrap().len());
    assert_eq!(handle.join().unwrap(), v);
}
