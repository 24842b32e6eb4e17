//! The `gonio` binary as a user runs it: outputs, messages and exit statuses.

use std::path::PathBuf;
use std::process::{Command, Output};

fn gonio(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gonio")).args(args).output().expect("the gonio binary runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "exit {:?}: {}", o.status.code(), stderr(o));
    serde_json::from_slice(&o.stdout).expect("valid JSON on stdout")
}

/// A fresh folder for one test's outputs.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gonio-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn models_lists_lambert_with_its_parameter() {
    let o = gonio(&["models"]);
    assert!(o.status.success());
    let text = stdout(&o);
    assert!(text.contains("lambert") && text.contains("--albedo") && text.contains("[0, 1]"), "{text}");
    assert!(text.contains("claims:   reciprocal, energy-conserving, isotropic"), "{text}");

    let list = json(&gonio(&["models", "--json"]));
    let lambert = list.as_array().unwrap().iter().find(|m| m["name"] == "lambert").expect("lambert listed");
    let albedo = &lambert["params"][0];
    assert_eq!(albedo["name"], "albedo");
    assert_eq!(albedo["kind"], "rgb");
    assert_eq!((albedo["min"].as_f64(), albedo["max"].as_f64()), (Some(0.0), Some(1.0)));
    assert_eq!(albedo["default"], serde_json::json!([0.8, 0.8, 0.8]));
    assert_eq!(lambert["claims"]["reciprocal"], true);
    // Every registered model is listed, with the names the registry gives.
    assert_eq!(list.as_array().unwrap().len(), brdf::models().len());
}

#[test]
fn eval_white_lambert_is_one_over_pi_with_cosine_pdf() {
    let inv_pi = std::f64::consts::FRAC_1_PI;
    // Unnormalised directions on purpose: wi = (1, 2, 3)/√14, so cos θi = 3/√14.
    for form in [&["--albedo", "1"][..], &["--albedo=1"][..], &["-p", "albedo=1"][..]] {
        let mut args = vec!["eval", "lambert", "--wi", "1,2,3", "--wo", "-0.5,0.1,0.2", "--json"];
        args.extend_from_slice(form);
        let v = json(&gonio(&args));
        for c in 0..3 {
            assert!((v["brdf"][c].as_f64().unwrap() - inv_pi).abs() < 1e-6, "{form:?}: {v}");
        }
        let cos_i = 3.0 / 14f64.sqrt();
        assert!((v["pdf"].as_f64().unwrap() - cos_i * inv_pi).abs() < 1e-6, "{v}");
        assert!((v["wi"][2].as_f64().unwrap() - cos_i).abs() < 1e-6, "{v}");
    }
    // RGB values per channel, and the text output names the unit.
    let v = json(&gonio(&["eval", "lambert", "--albedo", "0.1,0.2,0.3", "--wi", "0,0,1", "--wo", "0,0,1", "--json"]));
    for (c, a) in [0.1, 0.2, 0.3].iter().enumerate() {
        assert!((v["brdf"][c].as_f64().unwrap() - a * inv_pi).abs() < 1e-6, "{v}");
    }
    let o = gonio(&["eval", "lambert", "--wi", "0,0,1", "--wo", "0,0,1"]);
    assert!(o.status.success() && stdout(&o).contains("1/sr"), "{}", stdout(&o));
    // Below the surface: zero, not an error.
    let v = json(&gonio(&["eval", "lambert", "--wi", "0,0,-1", "--wo", "0,0,1", "--json"]));
    assert_eq!((v["brdf"][0].as_f64(), v["pdf"].as_f64()), (Some(0.0), Some(0.0)));
}

#[test]
fn usage_errors_explain_themselves_and_exit_2() {
    let cases: [(&[&str], &[&str]); 8] = [
        (&["eval", "lambertt", "--wi", "0,0,1", "--wo", "0,0,1"], &["unknown model 'lambertt'", "lambert"]),
        (&["eval", "lambert", "--albedo", "1.5", "--wi", "0,0,1", "--wo", "0,0,1"], &["albedo", "[0, 1]"]),
        (&["eval", "lambert", "--albedo", "x", "--wi", "0,0,1", "--wo", "0,0,1"], &["albedo", "'x'"]),
        (&["eval", "lambert", "--ks", "0.5", "--wi", "0,0,1", "--wo", "0,0,1"], &["no parameter 'ks'", "albedo"]),
        (&["eval", "lambert", "--wo", "0,0,1"], &["--wi"]),
        (&["eval", "lambert", "--wi", "0,0,0", "--wo", "0,0,1"], &["zero vector"]),
        (&["eval", "lambert", "--wi", "0,0,1", "--wo", "0,0,1", "--albedo"], &["--albedo needs a value"]),
        (&["plot", "lambert", "-o", "x.pdf"], &[".svg or .png"]),
    ];
    for (args, needles) in cases {
        let o = gonio(args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        for n in needles {
            assert!(err.contains(n), "{args:?}: '{n}' missing from: {err}");
        }
    }
    let o = gonio(&["plot", "lambert", "--overlay", "lambert:albedo=7", "-o", "x.svg"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--overlay item 'lambert:albedo=7'") && stderr(&o).contains("[0, 1]"),
        "{}",
        stderr(&o)
    );
    let o = gonio(&["check"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |k: usize| u32::from_be_bytes(bytes[k..k + 4].try_into().unwrap());
    (be(16), be(20))
}

/// Pixels within a small distance of an sRGB colour.
fn count_colour(png: &[u8], rgb: [u8; 3]) -> usize {
    let pm = resvg::tiny_skia::Pixmap::decode_png(png).expect("decodable PNG");
    pm.pixels()
        .iter()
        .filter(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue()].iter().zip(rgb).all(|(&a, b)| (i32::from(a) - i32::from(b)).abs() <= 24)
        })
        .count()
}

#[test]
fn plots_write_valid_svg_and_png() {
    let dir = scratch("plot");
    for kind in ["polar", "albedo", "slice"] {
        let svg = dir.join(format!("{kind}.svg"));
        let o = gonio(&["plot", "lambert", "--kind", kind, "--samples", "64", "-o", svg.to_str().unwrap()]);
        assert!(o.status.success(), "{kind}: {}", stderr(&o));
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"), "{kind}");
        // Curves are paths; the slice is an image.
        assert!(text.contains(if kind == "slice" { "<image" } else { "<path d=\"M" }), "{kind}");
        // The plot names its quantity and unit.
        assert!(text.contains("1/sr") || kind == "albedo", "{kind}");
    }
    assert!(std::fs::read_to_string(dir.join("slice.svg")).unwrap().contains("data:image/png;base64,iVBORw0KGgo"));

    // PNG at a chosen width keeps the aspect ratio; the lobe's colour (the first palette entry) is drawn.
    let (png, small, svg) = (dir.join("polar.png"), dir.join("small.png"), dir.join("overlay.svg"));
    for (out, width) in [(&png, None), (&small, Some("490")), (&svg, None)] {
        let mut args = vec!["plot", "lambert", "--overlay", "lambert:albedo=0.5", "-o", out.to_str().unwrap()];
        args.extend(width.map(|w| ["--width", w]).iter().flatten());
        let o = gonio(&args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let text = std::fs::read_to_string(&svg).unwrap();
    let attr = |name: &str| -> f64 {
        let start = text.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        text[start..].split('"').next().unwrap().parse().unwrap()
    };
    let (w, h) = (attr("width"), attr("height"));
    assert_eq!(png_size(&std::fs::read(&png).unwrap()), (w as u32, h as u32));
    assert_eq!(png_size(&std::fs::read(&small).unwrap()), (490, (490.0 * h / w).round() as u32));
    let bytes = std::fs::read(&png).unwrap();
    assert!(count_colour(&bytes, [0x00, 0x72, 0xB2]) > 100, "first lobe drawn");
    assert!(count_colour(&bytes, [0xD5, 0x5E, 0x00]) > 100, "overlay lobe drawn");

    // The slice PNG carries the raster: a white Lambert at φd = 0 is flat (the colour map's top)
    // where defined and grey where a direction is below the horizon.
    let png = dir.join("slice.png");
    let o = gonio(&["plot", "lambert", "--kind", "slice", "--phi-d", "0", "-o", png.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(png_size(&bytes), (720, 580));
    let top = count_colour(&bytes, [252, 253, 191]);
    let grey = count_colour(&bytes, [0x9a, 0x9a, 0x9a]);
    // 420 × 420 image, about half of it on each side of the diagonal θh + θd = 90°.
    assert!((70_000..100_000).contains(&top) && (70_000..100_000).contains(&grey), "top {top}, grey {grey}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn fresnel_plots_draw_each_models_interface_and_refuse_models_without_one() {
    let dir = scratch("fresnel");
    let svg = dir.join("fresnel.svg");
    let o = gonio(&[
        "plot",
        "dielectric",
        "--kind",
        "fresnel",
        "--overlay",
        "microfacet:material=Au",
        "-o",
        svg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&svg).unwrap();
    for row in
        ["dielectric: Rs", "dielectric: Rp", "dielectric: unpolarised", "dielectric: Schlick", "material=Au): Rp"]
    {
        assert!(text.contains(row), "legend row '{row}' missing");
    }
    // Four curves for each of the two models.
    assert_eq!(text.matches("<path d=\"M").count(), 8);
    let o = gonio(&["plot", "lambert", "--kind", "fresnel", "-o", svg.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("lambert") && stderr(&o).contains("no Fresnel term"), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn lobe3d_plots_draw_a_shaded_surface_per_model() {
    let dir = scratch("lobe3d");
    let (svg, png) = (dir.join("lobe.svg"), dir.join("lobe.png"));
    for out in [&svg, &png] {
        let args = ["plot", "ward", "--diffuse", "0.3", "--kind", "lobe3d", "--overlay", "mirror", "--normalize", "-o"];
        let o = gonio(&[&args[..], &[out.to_str().unwrap()]].concat());
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let text = std::fs::read_to_string(&svg).unwrap();
    // A facet per grid cell (45 × 72) of the lobe with a diffuse part; the mirror's delta lobe has none.
    assert_eq!(text.matches("<polygon points=").count(), 45 * 72, "facets");
    assert!(text.contains("mirror (delta lobe not drawn)") && text.contains("each scaled to its own peak"));
    assert!(png_size(&std::fs::read(&png).unwrap()).0 > 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn check_reports_a_table_and_exit_status() {
    let o = gonio(&["check", "lambert", "--albedo", "0.5"]);
    let text = stdout(&o);
    assert_eq!(o.status.code(), Some(0), "{text}{}", stderr(&o));
    for p in ["non-negativity", "reciprocity", "energy", "isotropy", "sample/pdf/eval", "chi-square"] {
        assert!(text.lines().any(|l| l.contains(p) && l.contains("yes") && l.contains("pass")), "{p}: {text}");
    }
    let v = json(&gonio(&["check", "lambert", "--json"]));
    assert_eq!(v["ok"], true);
    assert_eq!(v["cases"][0]["findings"].as_array().unwrap().len(), 6);
    let o = gonio(&["check", "--all", "--albedo", "1"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn raw_phong_visibly_fails_what_it_does_not_claim() {
    // The lecture's Phong is not reciprocal and, at ks = 1, ke = 1, reflects more than it receives;
    // it claims neither, so the check shows the failures and still exits 0.
    let o = gonio(&["check", "phong", "--ks", "1", "--ke", "1"]);
    let text = stdout(&o);
    assert_eq!(o.status.code(), Some(0), "{text}{}", stderr(&o));
    for p in ["reciprocity", "energy"] {
        assert!(text.lines().any(|l| l.trim_start().starts_with(p) && l.contains("fails, not claimed")), "{p}: {text}");
    }
    assert!(
        text.contains(
            "measured failing, not claimed by the model (as expected):\n  phong (ks=1, ke=1): reciprocity, energy"
        ),
        "{text}"
    );
}

#[test]
fn check_all_covers_every_case_and_its_exit_status_follows_the_claims() {
    let o = gonio(&["check", "--all", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON report");
    let cases: usize = brdf::models().iter().filter(|m| !m.requires_file()).map(|m| 1 + m.showcase.len()).sum();
    assert_eq!(v["cases"].as_array().unwrap().len(), cases);
    let ok = v["ok"].as_bool().unwrap();
    assert_eq!(ok, v["cases"].as_array().unwrap().iter().all(|c| c["ok"] == true));
    assert_eq!(o.status.code(), Some(if ok { 0 } else { 1 }), "{}", stderr(&o));
}

#[test]
fn demo_writes_both_plots_and_the_report() {
    let dir = scratch("demo");
    let o = gonio(&["demo", "--out-dir", dir.to_str().unwrap()]);
    let text = stdout(&o);
    for name in ["gonio-lobes.svg", "gonio-albedo.svg"] {
        let svg = std::fs::read_to_string(dir.join(name)).expect(name);
        assert!(svg.starts_with("<svg") && svg.contains("<path d=\"M"), "{name}");
        // Every lecture model that is registered appears in the legend.
        for m in ["lambert", "phong", "cook-torrance"].iter().filter(|m| brdf::find(m).is_ok()) {
            assert!(svg.contains(&format!(">{m}")), "{name} lacks {m}");
        }
    }
    assert!(text.contains("lambert (defaults), claims:") && text.contains("cases checked in"), "{text}");
    let ok = text.contains("every claimed property holds");
    assert_eq!(o.status.code(), Some(if ok { 0 } else { 1 }), "{text}{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn measure_writes_a_merl_table_that_loads_and_passes_check() {
    let dir = scratch("measure");
    let bin = dir.join("lambert.binary");
    let o = gonio(&["measure", "lambert", "--albedo", "0.1,0.2,0.3", "-o", bin.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("34992012 bytes"), "{}", stdout(&o));
    assert_eq!(std::fs::metadata(&bin).unwrap().len(), 34_992_012);
    // Read back as a model: a constant BRDF interpolates to itself.
    let v = json(&gonio(&[
        "eval",
        "merl",
        "--filename",
        bin.to_str().unwrap(),
        "--wi",
        "0.3,0.1,1",
        "--wo",
        "-0.4,0.2,1",
        "--json",
    ]));
    let inv_pi = std::f64::consts::FRAC_1_PI;
    for (c, a) in [0.1, 0.2, 0.3].iter().enumerate() {
        assert!((v["brdf"][c].as_f64().unwrap() - a * inv_pi).abs() < 1e-6, "{v}");
    }
    let o = gonio(&["check", "merl", "--filename", bin.to_str().unwrap(), "--json"]);
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON report");
    assert_eq!(r["ok"], true, "{r}");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // The measured model can itself be measured, but never over its own file.
    let o = gonio(&["measure", "merl", "--filename", bin.to_str().unwrap(), "-o", bin.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("refusing to overwrite the input"), "{}", stderr(&o));
    assert_eq!(std::fs::metadata(&bin).unwrap().len(), 34_992_012);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn measure_writes_the_tabulated_grid_and_bad_inputs_are_errors() {
    let dir = scratch("measure-csv");
    let csv = dir.join("ward.csv");
    let o = gonio(&[
        "measure",
        "ward",
        "--alpha",
        "0.3",
        "-o",
        csv.to_str().unwrap(),
        "--theta-i-steps",
        "3",
        "--theta-o-steps",
        "4",
        "--phi-o-steps",
        "5",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#') && !l.starts_with("theta")).collect();
    assert_eq!(rows.len(), 3 * 4 * 5);
    assert!(rows.iter().all(|r| r.split(',').count() == 7));
    assert_eq!(rows[1].split(',').take(4).collect::<Vec<_>>(), ["0", "0", "0", "72"]);

    let o = gonio(&["measure", "lambert", "-o", dir.join("x.pdf").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains(".binary"), "{}", stderr(&o));
    let o = gonio(&["measure", "lambert", "-o", csv.to_str().unwrap(), "--phi-o-steps", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--phi-o-steps 0"), "{}", stderr(&o));
    // A malformed MERL file names itself and the fault.
    let bad = dir.join("bad.binary");
    std::fs::write(&bad, [0u8, 0, 0, 90, 0, 0, 0, 90, 0, 0, 0, 180]).unwrap();
    let o = gonio(&["check", "merl", "--filename", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("bad.binary") && stderr(&o).contains("wrong endianness"), "{}", stderr(&o));
    let o = gonio(&["eval", "merl", "--wi", "0,0,1", "--wo", "0,0,1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("needs a file"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn fit_recovers_a_measured_model_ranks_all_and_plots() {
    let dir = scratch("fit");
    let bin = dir.join("ggx.binary");
    let o = gonio(&[
        "measure",
        "ggx",
        "--alpha",
        "0.2",
        "--fresnel",
        "none",
        "--diffuse",
        "0.1,0.2,0.3",
        "-o",
        bin.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = dir.join("fit.svg");
    let out = json(&gonio(&["fit", bin.to_str().unwrap(), "--model", "ggx", "--json", "-o", svg.to_str().unwrap()]));
    let f = &out["fits"][0];
    assert_eq!(f["model"], "ggx");
    // Noise-free data of the fitted model itself: the parameters come back within 2 %.
    assert!((f["shape"].as_f64().unwrap() / 0.2 - 1.0).abs() < 0.02, "{out}");
    for (c, want) in [0.1, 0.2, 0.3].into_iter().enumerate() {
        assert!((f["diffuse"][c].as_f64().unwrap() / want - 1.0).abs() < 0.02, "{out}");
        assert!((f["ks"][c].as_f64().unwrap() - 1.0).abs() < 0.02, "{out}");
    }
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.contains("θi = 40°"), "{text}");

    let o = gonio(&["fit", bin.to_str().unwrap(), "--all"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let first = text.lines().find(|l| l.trim_start().starts_with("1 ")).unwrap_or_default();
    assert!(first.contains("ggx"), "{text}");
    for m in ["ward", "cook-torrance", "modified-blinn-phong", "beckmann"] {
        assert!(text.contains(m), "{m} missing from\n{text}");
    }

    let o = gonio(&["fit", bin.to_str().unwrap(), "--model", "phong"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("ward, cook-torrance"), "{}", stderr(&o));
    let o = gonio(&["fit", dir.join("missing.binary").to_str().unwrap(), "--model", "ggx"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("missing.binary"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn polar_plots_turn_with_phi_i_for_anisotropic_models_only() {
    let dir = scratch("phi-i");
    let plot = |model: &[&str], phi: &str, name: &str| {
        let out = dir.join(name);
        let o = gonio(&[model, &["--kind", "polar", "--phi-i", phi, "-o", out.to_str().unwrap()]].concat());
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read_to_string(out).unwrap()
    };
    let ward = ["plot", "ward", "--alpha_u", "0.05", "--alpha_v", "0.4"];
    assert_ne!(plot(&ward, "0", "w0.svg"), plot(&ward, "90", "w90.svg"), "the lobe of an anisotropic model turns");
    assert_eq!(
        plot(&["plot", "ggx"], "0", "g0.svg"),
        plot(&["plot", "ggx"], "90", "g90.svg"),
        "an isotropic one does not"
    );
    let o = gonio(&["plot", "ggx", "--phi-i", "400", "-o", dir.join("x.svg").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--phi-i"), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn compare_lights_the_object_with_a_point_light_and_a_scaled_probe() {
    let dir = scratch("compare-light");
    let render = |extra: &[&str], name: &str| {
        let out = dir.join(name);
        let args =
            ["compare", "lambert", "--size", "64", "--spp", "4", "--backdrop", "none", "-o", out.to_str().unwrap()];
        let o = gonio(&[&args[..], extra].concat());
        assert!(o.status.success(), "{}", stderr(&o));
        render::Image::load(&out).unwrap()
    };
    // Bands of the sphere above and below its middle, clear of the label at the top.
    let half = |img: &render::Image, top: bool| -> f64 {
        let rows = if top { 28..32 } else { 40..52 };
        rows.flat_map(|y| (16..48).map(move |x| (x, y))).map(|(x, y)| f64::from(img.pixels[y * 64 + x].0[1])).sum()
    };
    let lit = render(&["--mesh", "sphere", "--env-scale", "0", "--light", "0,1,0.2"], "top.exr");
    assert!(
        half(&lit, true) > 10.0 * half(&lit, false),
        "lit from above: {} vs {}",
        half(&lit, true),
        half(&lit, false)
    );
    let dark = render(&["--mesh", "sphere", "--env-scale", "0"], "dark.exr");
    // The object's middle (the label is drawn along an edge).
    let centre: f64 =
        (28..36).flat_map(|y| (28..36).map(move |x| y * 64 + x)).map(|i| f64::from(dark.pixels[i].0[1])).sum();
    assert_eq!(centre, 0.0, "no probe and no point light: nothing lights the object");
    let probe = render(&["--mesh", "suzanne"], "suzanne.exr");
    assert!(probe.mean()[1] > 0.01, "{:?}", probe.mean());
    let o = gonio(&["compare", "lambert", "--light", "0,0,0", "-o", dir.join("x.png").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn png_plots_are_the_same_with_no_fonts_to_find() {
    // An empty home and font folders: a machine with no fonts installed. The PNG is the same
    // bytes as on this one, text included (the font is the binary's own).
    let dir = scratch("no-fonts");
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let (a, b) = (dir.join("a.png"), dir.join("b.png"));
    let args = ["plot", "phong", "--kind", "polar", "--theta-i", "30"];
    let o = gonio(&[&args[..], &["-o", a.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let o = Command::new(env!("CARGO_BIN_EXE_gonio"))
        .args([&args[..], &["-o", b.to_str().unwrap()]].concat())
        .env_clear()
        .env("HOME", &empty)
        .env("XDG_DATA_HOME", &empty)
        .env("XDG_DATA_DIRS", &empty)
        .env("FONTCONFIG_PATH", &empty)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    std::fs::remove_dir_all(&dir).unwrap();
}
