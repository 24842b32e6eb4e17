//! MERL load time: reading and parsing a full 35 MB table, and building its sampler.

use brdf::measured::merl::MerlTable;
use brdf::measured::MerlData;
use criterion::{criterion_group, criterion_main, Criterion};

fn bench_merl(c: &mut Criterion) {
    let model = brdf::build("ggx", &[("alpha", "0.15"), ("diffuse", "0.2")]).expect("ggx builds");
    let table = MerlTable::from_brdf(model.as_ref());
    let path = std::env::temp_dir().join(format!("gonio-bench-merl-{}.binary", std::process::id()));
    table.write(&path).expect("temp file");
    let bytes = std::fs::read(&path).expect("read back");
    let mut g = c.benchmark_group("merl");
    g.sample_size(10);
    g.bench_function("read file (35 MB)", |b| b.iter(|| MerlTable::read(&path).expect("valid")));
    g.bench_function("parse bytes", |b| b.iter(|| MerlTable::parse(&bytes, &path).expect("valid")));
    g.bench_function("build sampler", |b| b.iter(|| MerlData::new(table.clone())));
    g.bench_function("tabulate ggx", |b| b.iter(|| MerlTable::from_brdf(model.as_ref())));
    g.finish();
    let _ = std::fs::remove_file(&path);
}

criterion_group!(benches, bench_merl);
criterion_main!(benches);
