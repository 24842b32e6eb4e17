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
fn compare_writes_one_image_with_a_panel_per_model() {
    let d = temp_dir("compare");
    let o = d.join("cmp.png");
    let out =
        gonio(&["compare", "lambert", "phong:ke=10", "ggx", "--size", "24", "--spp", "1", "-o", o.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(png_size(&std::fs::read(&o).unwrap()), (72, 24));
    let out = gonio(&["compare", "nosuchmodel", "--size", "24", "-o", o.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
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
