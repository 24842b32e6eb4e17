//! `gonio render`, `compare` and `envmap` end to end, at small sizes.

use std::path::PathBuf;
use std::process::Command;

fn gonio(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_gonio")).args(args).output().expect("gonio runs")
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gonio-render-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[1..4], b"PNG");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn demo_render_has_the_requested_size_and_is_thread_independent() {
    let d = temp_dir("demo");
    let (a, b, e) = (d.join("a.png"), d.join("b.png"), d.join("c.exr"));
    let base = ["render", "--width", "48", "--height", "27", "--spp", "3", "--seed", "7"];
    let out = gonio(&[&base[..], &["--threads", "1", "-o", a.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = gonio(&[&base[..], &["--threads", "2", "-o", b.to_str().unwrap()]].concat());
    assert!(out.status.success());
    let (pa, pb) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert_eq!(png_size(&pa), (48, 27));
    assert_eq!(pa, pb, "same seed, 1 and 2 threads");
    let out = gonio(&[&base[..], &["-o", e.to_str().unwrap()]].concat());
    assert!(out.status.success());
    let img = render::Image::load(&e).unwrap();
    assert_eq!((img.width, img.height), (48, 27));
    let out = gonio(&["render", "--spp", "1", "-o", d.join("x.bmp").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn compare_lays_out_a_labelled_grid_of_models_by_sweep_values() {
    let d = temp_dir("compare");
    let o = d.join("grid.exr");
    let side = 256u32;
    let args =
        ["compare", "phong", "blinn-phong", "--sweep", "ke=5,50,500", "--size", "256", "--spp", "1", "--noise", "0"];
    let out = gonio(&[&args[..], &["-o", o.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    let order: Vec<_> = text.lines().filter_map(|l| l.split(':').next().filter(|_| l.contains("spp"))).collect();
    assert_eq!(
        order,
        [
            "phong (ke 5)",
            "phong (ke 50)",
            "phong (ke 500)",
            "blinn-phong (ke 5)",
            "blinn-phong (ke 50)",
            "blinn-phong (ke 500)"
        ],
        "a row per model, a column per value:\n{text}"
    );
    let img = render::Image::load(&o).unwrap();
    assert_eq!((img.width, img.height), (3 * side, 2 * side));
    // Fully covered label pixels are white exactly (1.0 in the linear image at exposure 0),
    // which no rendered pixel of this scene is: count them in each panel's top band and
    // everywhere else.
    let band = 48;
    for row in 0..2 {
        for col in 0..3 {
            let (x0, y0) = (col * side, row * side);
            let white = (y0..y0 + side)
                .flat_map(|y| (x0..x0 + side).map(move |x| (x, y)))
                .filter(|&(x, y)| img.get(x, y) == radiometry::Rgb::ONE)
                .map(|(_, y)| y - y0)
                .collect::<Vec<_>>();
            assert!(white.len() >= 5, "panel {row},{col}: {} white label pixels", white.len());
            assert!(white.iter().all(|&y| y < band), "panel {row},{col}: white below the label band: {white:?}");
        }
    }
    // The sweep shows: ke 5 and ke 500 differ below the labels.
    let below = |col: u32| -> f64 {
        (band..side)
            .flat_map(|y| (0..side).map(move |x| (x, y)))
            .map(|(x, y)| img.get(col * side + x, y).0[0] as f64)
            .sum()
    };
    assert_ne!(below(0), below(2));
    let out = gonio(&["compare", "ward", "--sweep", "ke=5", "--size", "24", "-o", o.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no parameter 'ke'"));
    let out = gonio(&["compare", "nosuchmodel", "--size", "24", "-o", o.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn compare_panels_stop_at_their_noise_threshold() {
    // A panel rendered to --noise 0.03, against the mean of two independent renders of 8 times
    // its samples each (other seeds): the display-value error it measures, less the reference's
    // own (estimated from its two halves), is within the threshold and 4 standard errors.
    let d = temp_dir("compare-noise");
    let run = |extra: &[&str], name: &str| {
        let o = d.join(name);
        let args = ["compare", "lambert", "--size", "64", "-o", o.to_str().unwrap()];
        let out = gonio(&[&args[..], extra].concat());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        (render::Image::load(&o).unwrap(), String::from_utf8_lossy(&out.stdout).into_owned())
    };
    let threshold = 0.03;
    let (img, text) = run(&["--noise", "0.03", "--spp", "4096"], "a.exr");
    let line = text.lines().next().unwrap();
    let spp: u32 = line.split(": ").nth(1).and_then(|r| r.split(' ').next()).and_then(|n| n.parse().ok()).unwrap();
    assert!(spp < 4096, "stopped by its noise: {line}");
    let n = (8 * spp).to_string();
    let (ra, _) = run(&["--noise", "0", "--spp", &n, "--seed", "1"], "ra.exr");
    let (rb, _) = run(&["--noise", "0", "--spp", &n, "--seed", "2"], "rb.exr");
    let d8 = |c: f32| render::io::png::srgb_encode(c).clamp(0.0, 1.0) as f64;
    let (mut e, mut half) = (Vec::new(), Vec::new());
    for ((p, a), b) in img.pixels.iter().zip(&ra.pixels).zip(&rb.pixels) {
        for c in 0..3 {
            let (a, b) = (d8(a.0[c]), d8(b.0[c]));
            if a != b {
                e.push((d8(p.0[c]) - 0.5 * (a + b)).powi(2));
                half.push((0.5 * (a - b)).powi(2));
            }
        }
    }
    let m = e.len() as f64;
    let mean = e.iter().sum::<f64>() / m;
    let reference = half.iter().sum::<f64>() / m;
    let measured = (mean - reference).max(0.0).sqrt();
    let sd = (e.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (m - 1.0)).sqrt();
    let slack = 4.0 * 0.5 * sd / (mean * m.sqrt());
    assert!(measured <= threshold * (1.0 + slack), "measured {measured:.4} at {spp} spp, slack {slack:.3}: {line}");
    assert!(measured > 0.25 * threshold, "the stop is not far below its threshold: {measured:.4} at {spp} spp");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn compare_puts_the_models_in_place_of_a_bsdf_of_a_scene_file() {
    let d = temp_dir("compare-scene");
    let scene = d.join("ball.xml");
    std::fs::write(
        &scene,
        r#"<scene version="3.0.0">
    <sensor type="perspective"><float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="48"/><rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <bsdf type="diffuse" id="ball"><rgb name="reflectance" value="0.5"/></bsdf>
    <shape type="sphere"><ref name="bsdf" id="ball"/></shape>
</scene>"#,
    )
    .unwrap();
    let o = d.join("cmp.exr");
    let base = ["compare", "lambert:albedo=0.2", "lambert:albedo=0.8", "--spp", "4", "--noise", "0", "--scene"];
    let out = gonio(&[&base[..], &[scene.to_str().unwrap(), "-o", o.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let img = render::Image::load(&o).unwrap();
    assert_eq!((img.width, img.height), (128, 48), "two panels of the scene's own film");
    // A white furnace: the sphere shows its albedo, whatever the lighting's noise (below the
    // labels, which take the panels' top rows).
    let (dim, bright) = (img.get(32, 40), img.get(96, 40));
    assert!((dim.0[1] - 0.2).abs() < 1e-3 && (bright.0[1] - 0.8).abs() < 1e-3, "{dim:?} {bright:?}");
    let out = gonio(&[&base[..], &[scene.to_str().unwrap(), "--bsdf", "cup", "-o", o.to_str().unwrap()]].concat());
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no <bsdf id=\"cup\">") && err.contains("ball"), "{err}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn envmap_converts_and_prints_irradiance() {
    let d = temp_dir("envmap");
    // A constant map: H = π L.
    let src = d.join("const.exr");
    let mut img = render::Image::new(32, 16);
    img.pixels.iter_mut().for_each(|p| *p = radiometry::Rgb::splat(2.0));
    img.save(&src).unwrap();
    let cross = d.join("cross.exr");
    let out = gonio(&["envmap", src.to_str().unwrap(), "--to", "cross", "--size", "8", "-o", cross.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("6.283"), "{text}");
    let c = render::Image::load(&cross).unwrap();
    assert_eq!((c.width, c.height), (32, 24));
    let ball = d.join("ball.hdr");
    let out = gonio(&["envmap", cross.to_str().unwrap(), "--to", "ball", "--size", "16", "-o", ball.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // Never over an input.
    let out = gonio(&["envmap", src.to_str().unwrap(), "-o", src.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(&d).unwrap();
}
