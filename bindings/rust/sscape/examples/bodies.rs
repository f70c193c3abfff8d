//! Five random bodies of the default model: their statures, and the first written as a glTF file.
//! usage: cargo run --example bodies [OUT_DIR]
fn main() -> Result<(), sscape::Error> {
    let out = std::env::args().nth(1).unwrap_or_else(|| ".".into());
    let model = sscape::Model::load_default()?;
    let (major, minor, patch) = sscape::version();
    println!("sscape {}.{}.{}: {} vertices, {} joints, {} shape components", major, minor, patch,
             model.vertex_count(), model.joint_count(), model.shape_count());
    let k = model.shape_count();
    let shapes = model.sample_shapes(1, 5, 2.5)?;
    let mut body = model.body()?;
    for i in 0..5 {
        body.set_shape(&shapes[i * k..(i + 1) * k])?;
        println!("body {}: stature {:.3} m, waist {:.3} m, mass {:.1} kg", i, body.measure_by_name("stature")?,
                 body.measure_by_name("waist_girth")?, body.measure_by_name("mass")?);
        if i == 0 {
            let path = std::path::Path::new(&out).join("body_0.glb");
            body.write(&path)?;
            println!("wrote {}", path.display());
        }
    }
    Ok(())
}
