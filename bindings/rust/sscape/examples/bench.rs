//! What calls cost through the crate: a trivial call, and a body's vertices after a shape change
//! (what an engine does per frame), as medians of 5 runs. Compare with tests/bindings/bench.c.
//! usage: cargo run --release --example bench
use std::time::Instant;

fn median(mut f: impl FnMut(usize), repeats: usize) -> f64 {
    let mut times: Vec<f64> = (0..5)
        .map(|_| {
            let start = Instant::now();
            for i in 0..repeats {
                f(i);
            }
            start.elapsed().as_secs_f64() * 1e9 / repeats as f64
        })
        .collect();
    times.sort_by(|a, b| a.partial_cmp(b).unwrap());
    times[2]
}

fn main() -> Result<(), sscape::Error> {
    let model = sscape::Model::load_default()?;
    let mut body = model.body()?;
    let k = model.shape_count();
    let shapes = model.sample_shapes(1, 16, 2.5)?;
    let mut sink = 0usize;
    let call = median(|_| sink += model.vertex_count(), 100_000);
    let vertices = median(|i| {
        body.set_shape(&shapes[(i % 16) * k..(i % 16 + 1) * k]).unwrap();
        sink += body.vertices().unwrap().len();
    }, 300);
    println!("rust: call {:.0} ns, shape+vertices {:.1} us ({})", call, vertices / 1000.0, sink % 2);
    Ok(())
}
