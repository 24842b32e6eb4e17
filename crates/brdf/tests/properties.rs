//! The property harness run on every registered model, with its defaults and each showcase
//! parameter set: no claimed property may fail. The lecture's raw Phong must be caught, and a
//! white Lambert must reflect everything at every angle (the furnace test).

use brdf::check::{albedo, check, Config, Property, Report};
use brdf::{models, Brdf};
use radiometry::{Rgb, Vec3};

/// Every model case: (label, model), defaults first, then each showcase set.
fn cases() -> Vec<(String, Box<dyn Brdf>)> {
    let mut out = Vec::new();
    // Models read from files have no defaults to check; tests/measured.rs checks one on a table.
    for m in models().iter().filter(|m| !m.requires_file()) {
        let sets = std::iter::once(&[][..]).chain(m.showcase.iter().copied());
        for set in sets {
            let label = if set.is_empty() {
                format!("{} (defaults)", m.name)
            } else {
                let args: Vec<String> = set.iter().map(|(k, v)| format!("--{k} {v}")).collect();
                format!("{} {}", m.name, args.join(" "))
            };
            let b = m.build_with(set).unwrap_or_else(|e| panic!("{label}: {e}"));
            out.push((label, b));
        }
    }
    out
}

/// Checks every case on all cores; the reports come back in case order.
fn check_all(cases: &[(String, Box<dyn Brdf>)], cfg: &Config) -> Vec<Report> {
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get()).min(cases.len().max(1));
    let mut reports: Vec<Option<Report>> = vec![None; cases.len()];
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                s.spawn(move || {
                    (t..cases.len()).step_by(threads).map(|i| (i, check(cases[i].1.as_ref(), cfg))).collect::<Vec<_>>()
                })
            })
            .collect();
        for h in handles {
            for (i, r) in h.join().expect("a check panicked") {
                reports[i] = Some(r);
            }
        }
    });
    reports.into_iter().map(|r| r.expect("every case checked")).collect()
}

#[test]
fn every_model_passes_every_property_it_claims() {
    let cases = cases();
    // One family for the Šidák correction: every χ² test of every case in this run.
    let cfg = Config { chi2_tests: cases.len(), ..Default::default() };
    let reports = check_all(&cases, &cfg);
    let mut failed = Vec::new();
    for ((label, _), r) in cases.iter().zip(&reports) {
        println!("== {label}\n{r}");
        if !r.ok() {
            failed.push(format!("== {label}\n{r}"));
        }
    }
    assert!(
        failed.is_empty(),
        "{} of {} cases fail a claimed property:\n{}",
        failed.len(),
        cases.len(),
        failed.join("\n")
    );
}

#[test]
fn raw_phong_is_caught_failing_reciprocity_and_energy() {
    let spec = brdf::find("phong").expect("the lecture's raw Phong is registered as 'phong'");
    assert!(!spec.showcase.is_empty(), "phong has showcase parameters");
    let cfg = Config::default();
    for set in spec.showcase {
        let b = spec.build_with(set).unwrap();
        let r = check(b.as_ref(), &cfg);
        let get = |p: Property| r.findings.iter().find(|f| f.property == p).unwrap();
        let (rec, en) = (get(Property::Reciprocity), get(Property::Energy));
        assert!(!rec.passed && rec.value > 0.1, "phong {set:?} should fail reciprocity:\n{r}");
        assert!(!en.passed && en.value > 1.0, "phong {set:?} should fail energy:\n{r}");
        // The model is honest about it, so the report as a whole does not fail.
        assert!(!rec.claimed && !en.claimed, "phong {set:?} must not claim what it breaks:\n{r}");
    }
}

#[test]
fn white_lambert_reflects_everything_at_every_angle() {
    let white = brdf::build("lambert", &[("albedo", "1")]).unwrap();
    for i in 0..=90 {
        // θo up to 89.9°, and at several azimuths.
        let theta = (i as f32).min(89.9).to_radians();
        let wo = radiometry::spherical_direction(theta, 0.37 * i as f32);
        let (mean, se) = albedo(white.as_ref(), wo, 4096, i as u64);
        assert_eq!(mean, Rgb::ONE, "albedo at θo = {}°", theta.to_degrees());
        assert_eq!(se, Rgb::ZERO);
    }
    // Below the surface nothing is reflected.
    let (mean, _) = albedo(white.as_ref(), Vec3::new(0.0, 0.6, -0.8), 1000, 1);
    assert_eq!(mean, Rgb::ZERO);
}

#[test]
fn eval_pdf_is_eval_and_pdf_bit_for_bit() {
    // Models that compute both at once (sharing the half vector, D, G) must not drift from the
    // separate calls the harness checks; directions over the whole sphere, wrapped in twosided too.
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut dir = move || {
        let (z, phi) = (2.0 * next() - 1.0, std::f32::consts::TAU * next());
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    };
    let mut cases = cases();
    for spec in ["ggx", "roughplastic"] {
        let front: std::sync::Arc<dyn Brdf> = brdf::build(spec, &[]).unwrap().into();
        let sided = brdf::two_sided::TwoSided::new(front.clone(), front).unwrap();
        cases.push((format!("twosided {spec}"), Box::new(sided)));
    }
    for (label, b) in &cases {
        for _ in 0..2000 {
            let (wi, wo) = (dir(), dir());
            let (f, p) = b.eval_pdf(wi, wo);
            let (fe, pe) = (b.eval(wi, wo), b.pdf(wi, wo));
            assert!(
                f.0.iter().zip(fe.0).all(|(a, b)| a.to_bits() == b.to_bits()) && p.to_bits() == pe.to_bits(),
                "{label}: eval_pdf({wi}, {wo}) = ({f:?}, {p}) but eval, pdf = ({fe:?}, {pe})"
            );
        }
    }
}
