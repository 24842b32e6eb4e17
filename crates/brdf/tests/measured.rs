//! Measured data: the MERL format round-trips an analytic model to the format's precision, its
//! malformed files give clear errors, the `merl` model is reciprocal bit for bit and passes the
//! property harness (sampling agreement and χ²), and the tabulated text format round-trips.

use brdf::check::{check_property, Config, Property};
use brdf::measured::merl::{self, entry_angles, from_half_diff, MerlTable, ENTRIES, FILE_BYTES, SCALE};
use brdf::measured::tabulated::{uniform_phi, uniform_theta, Tabulated};
use brdf::measured::{load_cached, Interpolation, MeasuredError, Merl};
use brdf::Brdf;
use radiometry::{Vec2, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::path::{Path, PathBuf};

/// A scratch folder, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(tag: &str) -> Self {
        let d = std::env::temp_dir().join(format!("gonio-measured-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        Scratch(d)
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// GGX gold with a diffuse base: a glossy lobe over a smooth term.
fn analytic() -> Box<dyn Brdf> {
    brdf::build("ggx", &[("alpha", "0.15"), ("diffuse", "0.2,0.3,0.4")]).unwrap()
}

fn upper(rng: &mut Pcg64) -> Vec3 {
    // Uniform on the hemisphere, kept off the horizon by 1e-3 so directions are valid.
    let z: f32 = rng.gen_range(1e-3..1.0);
    let p: f32 = rng.gen_range(0.0..std::f32::consts::TAU);
    let s = (1.0 - z * z).sqrt();
    Vec3::new(s * p.cos(), s * p.sin(), z)
}

#[test]
fn merl_round_trip_reproduces_the_model_to_the_format_precision() {
    let model = analytic();
    let t0 = std::time::Instant::now();
    let table = MerlTable::from_brdf(model.as_ref());
    let tabulate_s = t0.elapsed().as_secs_f64();
    let bytes = table.to_bytes();
    assert_eq!(bytes.len() as u64, FILE_BYTES);
    assert_eq!(bytes.len(), 34_992_012);
    // Header: 90, 90, 180 as little-endian int32.
    assert_eq!(&bytes[..12], &[90, 0, 0, 0, 90, 0, 0, 0, 180, 0, 0, 0]);
    // The first green value sits one channel (1,458,000 float64) after the first red one and is
    // stored divided by its scale.
    let raw = |k: usize| f64::from_le_bytes(bytes[12 + 8 * k..20 + 8 * k].try_into().unwrap());
    let e0 = table.entries()[0];
    assert_eq!(raw(0), f64::from(e0[0]) / SCALE[0]);
    assert_eq!(raw(ENTRIES), f64::from(e0[1]) / SCALE[1]);

    let dir = Scratch::new("roundtrip");
    let path = dir.path("ggx.binary");
    table.write(&path).unwrap();
    assert_eq!(std::fs::metadata(&path).unwrap().len(), 34_992_012);
    let t1 = std::time::Instant::now();
    let back = MerlTable::read(&path).unwrap();
    let load_s = t1.elapsed().as_secs_f64();
    // float64 holds every f32 exactly; ×scale then ÷scale can move the last f64 bit, which the
    // f32 rounding absorbs: the relative error allowed is one f32 ulp (2⁻²³).
    let mut worst = 0.0f64;
    for (a, b) in table.entries().iter().zip(back.entries()) {
        for c in 0..3 {
            if a[c] < 0.0 {
                assert!(b[c] < 0.0, "not-measured entries stay not measured");
                continue;
            }
            let rel = (f64::from(a[c]) - f64::from(b[c])).abs() / f64::from(a[c]).max(1e-30);
            worst = worst.max(rel);
        }
    }
    assert!(worst <= 2f64.powi(-23), "worst relative round-trip error {worst:e}");
    eprintln!("tabulate {tabulate_s:.3} s, load {load_s:.3} s, worst round-trip error {worst:e}");

    // At an entry's own directions, the loaded model gives the analytic model's value.
    let m = Merl::open(&path, Interpolation::Linear).unwrap();
    let mut rng = Pcg64::seed_from_u64(11);
    let mut tested = 0;
    while tested < 2000 {
        let (ih, id, ip) = (rng.gen_range(0..90), rng.gen_range(0..90), rng.gen_range(0..180));
        let a = entry_angles(ih, id, ip);
        let (wi, wo) = from_half_diff(a.theta_h, a.theta_d, a.phi_d);
        if wi.z <= 1e-3 || wo.z <= 1e-3 {
            continue;
        }
        let (got, want) = (m.eval(wi, wo), model.eval(wi, wo));
        for c in 0..3 {
            // The lookup sits within ~1e-9 of the node: neighbours weigh at most that much.
            let tol = 1e-4 * want.0[c].abs() + 1e-6;
            assert!((got.0[c] - want.0[c]).abs() <= tol, "entry ({ih},{id},{ip}): {got:?} vs {want:?}");
        }
        tested += 1;
    }

    // Between entries: the interpolation error against the analytic model, reported.
    let mut errs: Vec<f64> = (0..20_000)
        .filter_map(|_| {
            let (wi, wo) = (upper(&mut rng), upper(&mut rng));
            let want = f64::from(model.eval(wi, wo).luminance());
            (want > 1e-3).then(|| (f64::from(m.eval(wi, wo).luminance()) - want).abs() / want)
        })
        .collect();
    errs.sort_by(f64::total_cmp);
    for theta_o in [10.0f32, 40.0, 70.0] {
        let wo = Vec3::new(theta_o.to_radians().sin(), 0.0, theta_o.to_radians().cos());
        let (am, sm) = brdf::check::albedo(&m, wo, 1 << 16, 5);
        let (aa, sa) = brdf::check::albedo(model.as_ref(), wo, 1 << 16, 5);
        eprintln!("albedo at θo {theta_o}: merl {am:?} ± {sm:?}, analytic {aa:?} ± {sa:?}");
        // Independent estimates (different samplers): 4σ of their difference. The interpolation
        // bias is not in σ; it measures far below it here (errors above are ~1e-3 pointwise).
        for c in 0..3 {
            let sigma = (sm.0[c].powi(2) + sa.0[c].powi(2)).sqrt();
            assert!((am.0[c] - aa.0[c]).abs() <= 4.0 * sigma, "albedo at θo {theta_o}, channel {c}");
        }
    }
    let q = |f: f64| errs[((errs.len() - 1) as f64 * f) as usize];
    eprintln!(
        "interpolated vs analytic, relative error: median {:.2e}, 90% {:.2e}, 99% {:.2e}",
        q(0.5),
        q(0.9),
        q(0.99)
    );
}

#[test]
fn a_constant_brdf_interpolates_exactly_and_lookups_are_reciprocal_bit_for_bit() {
    let lambert = brdf::build("lambert", &[("albedo", "0.5,0.6,0.7")]).unwrap();
    let m = Merl::from_table(MerlTable::from_brdf(lambert.as_ref()), Interpolation::Linear);
    let n = Merl { data: m.data.clone(), interpolation: Interpolation::Nearest };
    let mut rng = Pcg64::seed_from_u64(3);
    for _ in 0..20_000 {
        let (wi, wo) = (upper(&mut rng), upper(&mut rng));
        let (a, b) = (m.eval(wi, wo), m.eval(wo, wi));
        assert_eq!(a.0.map(f32::to_bits), b.0.map(f32::to_bits), "{wi:?} {wo:?}");
        assert_eq!(n.eval(wi, wo).0.map(f32::to_bits), n.eval(wo, wi).0.map(f32::to_bits));
        if wi.z > 0.05 && wo.z > 0.05 {
            let want = lambert.eval(wi, wo);
            for c in 0..3 {
                // A weighted mean of equal f32 values: a few ulps of rounding at most.
                assert!((a.0[c] - want.0[c]).abs() <= 4e-7, "{a:?} vs {want:?} at {wi:?} {wo:?}");
            }
        }
    }
}

#[test]
fn the_merl_model_passes_the_property_harness() {
    let dir = Scratch::new("check");
    let path = dir.path("ggx.binary");
    MerlTable::from_brdf(analytic().as_ref()).write(&path).unwrap();
    let b = brdf::build("merl", &[("filename", path.to_str().unwrap())]).unwrap();
    // Four properties checked together: Šidák over four model cases.
    let cfg = Config { chi2_tests: 4, ..Config::default() };
    for p in [Property::NonNegative, Property::Reciprocity, Property::Isotropy, Property::Sampling, Property::ChiSquare]
    {
        let f = check_property(b.as_ref(), p, &cfg);
        eprintln!("{f}");
        assert!(f.passed, "{f}");
    }
    // A sharper lobe stresses the sampler's tables.
    let sharp = brdf::build("ggx", &[("alpha", "0.05")]).unwrap();
    let m = Merl::from_table(MerlTable::from_brdf(sharp.as_ref()), Interpolation::Linear);
    let f = check_property(&m, Property::ChiSquare, &cfg);
    eprintln!("sharp: {f}");
    assert!(f.passed, "{f}");
    let f = check_property(&m, Property::Sampling, &cfg);
    assert!(f.passed, "{f}");
}

#[test]
fn the_merl_model_never_returns_nan_or_inf() {
    let m = Merl::from_table(MerlTable::from_brdf(analytic().as_ref()), Interpolation::Linear);
    let mut rng = Pcg64::seed_from_u64(9);
    let edge = [0.0f32, 1e-7, -1e-7, 1e-4, 1.0, 1.0 - 1e-7];
    let dir = |rng: &mut Pcg64| {
        let z = if rng.gen_bool(0.3) { edge[rng.gen_range(0..edge.len())] } else { rng.gen_range(-1.0..1.0) };
        let p: f32 = rng.gen_range(0.0..std::f32::consts::TAU);
        let s = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(s * p.cos(), s * p.sin(), z)
    };
    for _ in 0..100_000 {
        let (wi, wo) = (dir(&mut rng), dir(&mut rng));
        let v = m.eval(wi, wo);
        assert!(v.is_finite() && v.min_channel() >= 0.0, "{v:?}");
        let p = m.pdf(wi, wo);
        assert!(p.is_finite() && p >= 0.0);
        if let Some(s) = m.sample(wo, rng.gen(), Vec2::new(rng.gen(), rng.gen())) {
            assert!(s.pdf > 0.0 && s.pdf.is_finite() && s.weight.is_finite() && s.wi.z > 0.0, "{s:?}");
        }
    }
}

fn parse_err(bytes: &[u8]) -> String {
    MerlTable::parse(bytes, Path::new("bad.binary")).unwrap_err().to_string()
}

#[test]
fn malformed_merl_files_give_clear_errors() {
    let good = MerlTable::from_brdf(brdf::build("lambert", &[]).unwrap().as_ref()).to_bytes();
    assert!(MerlTable::parse(&good, Path::new("ok.binary")).is_ok());

    let e = parse_err(&good[..good.len() - 8]);
    assert!(e.contains("bad.binary") && e.contains("truncated") && e.contains("34992012"), "{e}");
    let e = parse_err(&good[..7]);
    assert!(e.contains("truncated header"), "{e}");
    let e = parse_err(&[]);
    assert!(e.contains("truncated"), "{e}");
    let mut long = good.clone();
    long.push(0);
    assert!(parse_err(&long).contains("trailing bytes"));

    let mut dims = good.clone();
    dims[8..12].copy_from_slice(&360i32.to_le_bytes());
    let e = parse_err(&dims);
    assert!(e.contains("dimensions [90, 90, 360]") && e.contains("90 θh × 90 θd × 180 φd"), "{e}");

    let mut big = good.clone();
    for k in 0..3 {
        let v = i32::from_le_bytes(big[4 * k..4 * k + 4].try_into().unwrap());
        big[4 * k..4 * k + 4].copy_from_slice(&v.to_be_bytes());
    }
    let e = parse_err(&big);
    assert!(e.contains("wrong endianness"), "{e}");

    // A NaN in the green channel at entry (1, 2, 3).
    let mut nan = good.clone();
    let k = merl::ENTRIES + merl::entry_index(1, 2, 3);
    nan[12 + 8 * k..20 + 8 * k].copy_from_slice(&f64::NAN.to_le_bytes());
    let e = parse_err(&nan);
    assert!(
        e.contains("green") && e.contains("θh index 1") && e.contains("θd index 2") && e.contains("φd index 3"),
        "{e}"
    );
    let mut inf = good.clone();
    inf[12..20].copy_from_slice(&f64::INFINITY.to_le_bytes());
    assert!(parse_err(&inf).contains("not a finite number"));

    // Through the registry: the parameter error names the file and the fault.
    let dir = Scratch::new("bad");
    let p = dir.path("short.binary");
    std::fs::write(&p, &good[..1000]).unwrap();
    let e = brdf::build("merl", &[("filename", p.to_str().unwrap())]).unwrap_err().to_string();
    assert!(e.contains("filename") && e.contains("short.binary") && e.contains("truncated"), "{e}");
    let missing = dir.path("missing.binary");
    let e = brdf::build("merl", &[("filename", missing.to_str().unwrap())]).unwrap_err().to_string();
    assert!(e.contains("missing.binary"), "{e}");
    let e = brdf::build("merl", &[]).unwrap_err().to_string();
    assert!(e.contains("needs a file"), "{e}");
    assert!(matches!(MerlTable::read(&missing), Err(MeasuredError::Io { .. })));
}

#[test]
fn loading_a_file_twice_reuses_it_until_it_changes() {
    let dir = Scratch::new("cache");
    let p = dir.path("l.binary");
    let t = MerlTable::from_brdf(brdf::build("lambert", &[]).unwrap().as_ref());
    t.write(&p).unwrap();
    let a = load_cached(&p).unwrap();
    let b = load_cached(&p).unwrap();
    assert!(std::sync::Arc::ptr_eq(&a, &b));
    // A file with other contents (and so, here, another length) is read afresh.
    let mut bytes = t.to_bytes();
    bytes.push(0);
    std::fs::write(&p, &bytes).unwrap();
    assert!(load_cached(&p).unwrap_err().to_string().contains("trailing"));
}

#[test]
fn tabulated_text_round_trips_and_interpolates() {
    let model = analytic();
    let t = Tabulated::from_brdf(model.as_ref(), uniform_theta(9), vec![0.0], uniform_theta(18), uniform_phi(24));
    assert_eq!(t.values.len(), 9 * 18 * 24);
    let text = t.to_text();
    assert!(text.starts_with("# gonio tabulated BRDF v1\n"));
    let back = Tabulated::parse(&text, Path::new("t.csv")).unwrap();
    // `{}` writes the shortest decimal that reads back to the same f32: exact.
    assert_eq!(back, t);
    // Rows in any order, whitespace separators, no column line: the same table.
    let mut lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#') && !l.starts_with("theta")).collect();
    lines.reverse();
    let shuffled = lines.iter().map(|l| l.replace(',', " ")).collect::<Vec<_>>().join("\n");
    assert_eq!(Tabulated::parse(&shuffled, Path::new("t.txt")).unwrap(), t);

    // At grid points the lookup returns the measurement; rotating the pair about the normal
    // changes nothing (one plane of incidence is stored).
    let d = |t: f64, p: f64| {
        let (t, p) = (t.to_radians(), p.to_radians());
        Vec3::new((t.sin() * p.cos()) as f32, (t.sin() * p.sin()) as f32, t.cos() as f32)
    };
    for (ti, to, po) in [(20.0, 30.0, 165.0), (50.0, 45.0, 0.0), (0.0, 10.0, 345.0)] {
        let want = model.eval(d(ti, 0.0), d(to, po));
        for rot in [0.0, 77.0] {
            let got = t.lookup(d(ti, rot), d(to, po + rot));
            for c in 0..3 {
                assert!((got.0[c] - want.0[c]).abs() <= 1e-4 * want.0[c] + 1e-6, "{got:?} vs {want:?}");
            }
        }
    }
    // A constant BRDF interpolates to itself anywhere, φo wrapping past 345°.
    let lambert = brdf::build("lambert", &[]).unwrap();
    let l = Tabulated::from_brdf(lambert.as_ref(), uniform_theta(6), vec![0.0], uniform_theta(6), uniform_phi(12));
    let v = l.lookup(d(33.0, 10.0), d(47.0, 359.0));
    assert!((v.0[0] - 0.8 / std::f32::consts::PI).abs() < 1e-6, "{v:?}");

    let dir = Scratch::new("tab");
    let p = dir.path("t.csv");
    t.write(&p).unwrap();
    assert_eq!(Tabulated::read(&p).unwrap(), t);
}

#[test]
fn malformed_tables_give_clear_errors() {
    let e = |s: &str| Tabulated::parse(s, Path::new("m.csv")).unwrap_err().to_string();
    let full = "theta_i,phi_i,theta_o,phi_o,r,g,b\n0,0,0,0,1,1,1\n0,0,10,0,1,1,1\n";
    assert!(Tabulated::parse(full, Path::new("m.csv")).is_ok());
    let m = e("0,0,0,0,1,1,1\n0,0,10,0,1,1,1\n10,0,0,0,1,1,1\n");
    assert!(m.contains("m.csv") && m.contains("not a full grid") && m.contains("(10, 0, 10, 0)"), "{m}");
    assert!(e("0,0,0,0,1,1,1\n0,0,0,0,2,2,2\n").contains("line 2: a second measurement"));
    assert!(e("0,0,0,0,1,1\n").contains("line 1: 6 fields"));
    assert!(e("0,0,0,0,NaN,1,1\n").contains("not a finite number"));
    assert!(e("0,0,0,0,x,1,1\n").contains("'x' is not a number"));
    assert!(e("0,0,95,0,1,1,1\n").contains("theta_o = 95 is outside [0, 90]"));
    assert!(e("# nothing\n").contains("no measurements"));
}
