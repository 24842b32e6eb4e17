//! Throughput of every registered model with its default parameters: `eval` on fixed pairs of
//! upper-hemisphere directions and `sample` on fixed outgoing directions and random numbers.
//! Run: `cargo bench -p brdf -- --warm-up-time 1 --measurement-time 2`.

use brdf::{models, Brdf};
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use radiometry::{Vec2, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// Inputs per batch: enough to average over the lobe, few enough to stay in L1/L2.
const N: usize = 4096;

/// A uniformly distributed direction strictly above the surface.
fn upper(rng: &mut Pcg64) -> Vec3 {
    loop {
        let z: f32 = rng.gen();
        let phi = rng.gen::<f32>() * std::f32::consts::TAU;
        let s = (1.0 - z * z).max(0.0).sqrt();
        if z > 0.0 {
            return Vec3::new(s * phi.cos(), s * phi.sin(), z);
        }
    }
}

fn bench_models(c: &mut Criterion) {
    let mut rng = Pcg64::seed_from_u64(0xBE9C);
    let pairs: Vec<(Vec3, Vec3)> = (0..N).map(|_| (upper(&mut rng), upper(&mut rng))).collect();
    let draws: Vec<(Vec3, f32, Vec2)> =
        (0..N).map(|_| (upper(&mut rng), rng.gen(), Vec2::new(rng.gen(), rng.gen()))).collect();

    let mut eval = c.benchmark_group("eval");
    eval.throughput(Throughput::Elements(N as u64));
    for m in models().iter().filter(|m| !m.requires_file()) {
        let b: Box<dyn Brdf> = m.build_with(&[]).expect("defaults build");
        eval.bench_function(m.name, |bench| {
            bench.iter(|| {
                let mut acc = 0.0f32;
                for &(wi, wo) in &pairs {
                    acc += b.eval(black_box(wi), black_box(wo)).0[0];
                }
                acc
            })
        });
    }
    eval.finish();

    let mut sample = c.benchmark_group("sample");
    sample.throughput(Throughput::Elements(N as u64));
    for m in models().iter().filter(|m| !m.requires_file()) {
        let b: Box<dyn Brdf> = m.build_with(&[]).expect("defaults build");
        sample.bench_function(m.name, |bench| {
            bench.iter(|| {
                let mut acc = 0.0f32;
                for &(wo, uc, u) in &draws {
                    if let Some(s) = b.sample(black_box(wo), black_box(uc), black_box(u)) {
                        acc += s.weight.0[0];
                    }
                }
                acc
            })
        });
    }
    sample.finish();
}

criterion_group!(benches, bench_models);
criterion_main!(benches);
