//! No model may return NaN or infinity, whatever its parameters (drawn across their declared
//! ranges, endpoints included) and whatever the directions (grazing, on and below the horizon):
//! 10⁶ direction pairs over all models, each given to eval, pdf and sample.

use brdf::{models, Brdf, ModelSpec, ParamKind, ParamSpec};
use radiometry::{Vec2, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::TAU;

/// Direction pairs in all, shared out among the models.
const TOTAL_PAIRS: usize = 1_000_000;
/// Pairs per parameter draw.
const PAIRS_PER_SET: usize = 500;

/// A value of `spec` as text: endpoints a quarter of the time each, every option in turn on odd
/// draws (so each is reached) and at random on even ones.
fn draw(spec: &ParamSpec, k: usize, rng: &mut Pcg64) -> String {
    let real = |min: f64, max: f64, rng: &mut Pcg64| match rng.gen_range(0..4) {
        0 => min,
        1 => max,
        _ => rng.gen_range(min..=max),
    };
    let pick = |n: usize, rng: &mut Pcg64| if k % 2 == 1 { (k / 2) % n } else { rng.gen_range(0..n) };
    match &spec.kind {
        ParamKind::Float { min, max } => format!("{}", real(*min, *max, rng)),
        ParamKind::Rgb { min, max } => {
            let c: Vec<String> = (0..3).map(|_| format!("{}", real(*min, *max, rng))).collect();
            c.join(",")
        }
        ParamKind::Choice(opts) => opts[pick(opts.len(), rng)].to_string(),
        ParamKind::Bool => (pick(2, rng) == 1).to_string(),
        // Models read from files are skipped below; tests/measured.rs stresses them on a table.
        ParamKind::Path => String::new(),
        // Wrappers keep their default nested model; every model is stressed on its own.
        ParamKind::Model => spec.default.to_string(),
    }
}

/// cos θ values at and around the horizon and the normal.
const EDGE_COS: [f64; 12] = [0.0, -0.0, 1e-7, -1e-7, 1e-6, -1e-6, 1e-4, 1e-3, 1.0, -1.0, 1.0 - 1e-7, 1.0 - 1e-6];

/// A direction: half uniform on the sphere, a quarter on the special cos θ values, a quarter
/// within a log-uniform distance (down to 1e-8) of the horizon on either side.
fn direction(rng: &mut Pcg64) -> Vec3 {
    let c = match rng.gen_range(0..4) {
        0 | 1 => rng.gen_range(-1.0..=1.0),
        2 => EDGE_COS[rng.gen_range(0..EDGE_COS.len())],
        _ => 10f64.powf(rng.gen_range(-8.0..-1.0)) * if rng.gen() { 1.0 } else { -1.0 },
    };
    let phi = rng.gen::<f64>() * TAU;
    let s = (1.0 - c * c).max(0.0).sqrt();
    Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32)
}

/// A sampler input: usually random, sometimes exactly 0 or the largest f32 below 1.
fn unit(rng: &mut Pcg64) -> f32 {
    match rng.gen_range(0..8) {
        0 => 0.0,
        1 => 1.0 - f32::EPSILON / 2.0,
        _ => rng.gen(),
    }
}

/// Runs `pairs` pairs through one model with random parameter sets; returns the problems found.
fn stress(m: &ModelSpec, pairs: usize, rng: &mut Pcg64) -> (Vec<String>, usize) {
    let specs = (m.params)();
    let mut problems = Vec::new();
    let mut built = 0;
    let mut k = 0;
    let mut done = 0;
    while done < pairs {
        let values: Vec<(&str, String)> = specs.iter().map(|s| (s.name, draw(s, k, rng))).collect();
        k += 1;
        let given: Vec<(&str, &str)> = values.iter().map(|(n, v)| (*n, v.as_str())).collect();
        let b: Box<dyn Brdf> = match m.build_with(&given) {
            Ok(b) => b,
            // Parameters valid alone but not together are refused with an error: also fine.
            Err(_) if k < 100 * (pairs / PAIRS_PER_SET + 1) => continue,
            Err(e) => panic!("{}: no parameter draw builds ({e})", m.name),
        };
        built += 1;
        let mut report = |what: String| {
            if problems.len() < 10 {
                problems.push(format!("{} {given:?}: {what}", m.name));
            }
        };
        for _ in 0..PAIRS_PER_SET {
            let (wi, wo) = (direction(rng), direction(rng));
            let f = b.eval(wi, wo);
            if !f.is_finite() || f.min_channel() < 0.0 {
                report(format!("eval(wi {wi:?}, wo {wo:?}) = {:?}", f.0));
            }
            let p = b.pdf(wi, wo);
            if !p.is_finite() || p < 0.0 {
                report(format!("pdf(wi {wi:?}, wo {wo:?}) = {p}"));
            }
            let (uc, u) = (unit(rng), Vec2::new(unit(rng), unit(rng)));
            if let Some(s) = b.sample(wo, uc, u) {
                let finite = s.wi.is_finite() && s.pdf.is_finite() && s.weight.is_finite();
                if !finite || s.pdf <= 0.0 || s.weight.min_channel() < 0.0 {
                    report(format!("sample(wo {wo:?}, uc {uc}, u {u:?}) = {s:?}"));
                }
            }
        }
        done += PAIRS_PER_SET;
    }
    (problems, built)
}

#[test]
fn no_model_returns_nan_inf_or_negative_values() {
    let all: Vec<&ModelSpec> = models().iter().filter(|m| !m.requires_file()).collect();
    let per_model = TOTAL_PAIRS / all.len().max(1);
    let mut problems = Vec::new();
    for (i, m) in all.iter().enumerate() {
        let mut rng = Pcg64::seed_from_u64(0x0B05_7000 + i as u64);
        let (p, built) = stress(m, per_model, &mut rng);
        assert!(built > 0, "{}", m.name);
        problems.extend(p);
    }
    assert!(problems.is_empty(), "{} problems (first 10 per model):\n{}", problems.len(), problems.join("\n"));
}

#[test]
fn parameter_draws_reach_the_endpoints_and_every_option() {
    // The generator itself: over 40 draws, each option of a 4-way choice and both endpoints appear.
    let mut rng = Pcg64::seed_from_u64(5);
    let choice = ParamSpec::choice("c", &["a", "b", "c", "d"], "a", "");
    let seen: std::collections::HashSet<String> = (0..40).map(|k| draw(&choice, k, &mut rng)).collect();
    assert_eq!(seen.len(), 4);
    let float = ParamSpec::float("x", 0.25, 2.0, 1.0, "");
    let v: Vec<f64> = (0..40).map(|k| draw(&float, k, &mut rng).parse().unwrap()).collect();
    assert!(v.contains(&0.25) && v.contains(&2.0) && v.iter().all(|x| (0.25..=2.0).contains(x)));
}
