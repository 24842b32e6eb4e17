//! The per-sample pieces of shading that a path tracer pays for: visible-normal sampling of each
//! distribution, the conductor Fresnel term, and building a rough plastic's coat tables.
//! Run: `cargo bench -p brdf --bench shading -- --warm-up-time 1 --measurement-time 2`.

use brdf::fresnel::{conductor_rgb, AU};
use brdf::microfacet::{Beckmann, Ggx, Ndf};
use brdf::plastic::RoughPlastic;
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use radiometry::{Rgb, Vec2, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// Inputs per batch.
const N: usize = 4096;

fn bench_shading(c: &mut Criterion) {
    let mut rng = Pcg64::seed_from_u64(0x5EED);
    let draws: Vec<(Vec3, Vec2)> = (0..N)
        .map(|_| {
            // Cosine-distributed viewing directions, as a path tracer's bounces see them.
            let (r, phi) = (rng.gen::<f32>().sqrt(), rng.gen::<f32>() * std::f32::consts::TAU);
            let wo = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - r * r).max(1e-4).sqrt()).normalize();
            (wo, Vec2::new(rng.gen(), rng.gen()))
        })
        .collect();

    let mut g = c.benchmark_group("sample_visible");
    g.throughput(Throughput::Elements(N as u64));
    let beckmann = Beckmann::new(0.1, 0.1);
    g.bench_function("beckmann", |b| {
        b.iter(|| draws.iter().map(|&(wo, u)| beckmann.sample_visible(black_box(wo), black_box(u)).z).sum::<f32>())
    });
    let ggx = Ggx::new(0.1, 0.1);
    g.bench_function("ggx", |b| {
        b.iter(|| draws.iter().map(|&(wo, u)| ggx.sample_visible(black_box(wo), black_box(u)).z).sum::<f32>())
    });
    g.finish();

    let mut f = c.benchmark_group("fresnel");
    f.throughput(Throughput::Elements(N as u64));
    f.bench_function("conductor_rgb", |b| {
        b.iter(|| draws.iter().map(|&(wo, _)| conductor_rgb(black_box(wo.z), AU.eta, AU.k).0[0]).sum::<f32>())
    });
    f.finish();

    let mut t = c.benchmark_group("roughplastic_tables");
    t.sample_size(10);
    for dist in ["beckmann", "ggx"] {
        t.bench_function(dist, |b| {
            b.iter(|| {
                RoughPlastic::new(dist, black_box(0.1), 1.5, Rgb::splat(0.5), Rgb::ONE, false)
                    .map(|m| m.transmittance(0.5))
            })
        });
    }
    t.finish();
}

criterion_group!(benches, bench_shading);
criterion_main!(benches);
