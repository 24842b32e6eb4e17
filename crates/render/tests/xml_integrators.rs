//! What a scene's `<integrator>` means, checked on closed forms (every expected value here is
//! also what Mitsuba 3.9.1 renders for the same file): `max_depth` counts the camera's vertex
//! and every pass through a `null` surface, `hide_emitters` hides the environment from the
//! camera (also through null surfaces) but not from the light it casts, and `direct`'s
//! `emitter_samples` averages area-light samples but adds delta lights once per sample.

use render::renderer::{render, RenderOptions};
use render::xml::load_scene_str;
use std::path::Path;

/// A 16×16 scene: a camera at z = `cam_z` looking down −z with a 10° field of view, `body`
/// and `integrator` around it.
fn scene(integrator: &str, cam_z: f32, body: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
  {integrator}
  <sensor type="perspective"><float name="fov" value="10"/>
    <transform name="to_world"><lookat origin="0, 0, {cam_z}" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
      <rfilter type="box"/></film>
  </sensor>
  {body}
</scene>"#
    )
}

/// The red channel of every pixel, rendered at `spp` with seed `seed`.
fn pixels(xml: &str, spp: u32, seed: u64) -> Vec<f64> {
    let s = load_scene_str(xml, Path::new("."), &[]).unwrap_or_else(|e| panic!("{e}"));
    let opts = RenderOptions { spp, seed, threads: 0, integrator: s.integrator, ..Default::default() };
    let img = render(&s.scene, &opts, |_| {});
    img.pixels.iter().map(|p| p.0[0] as f64).collect()
}

/// Mean and standard error of the mean of independent estimates.
fn mean_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// Asserts the pixels' mean is `expected` within four standard errors (and f32 rounding).
fn assert_mean(label: &str, v: &[f64], expected: f64) {
    let (m, se) = mean_se(v);
    assert!(
        (m - expected).abs() <= 4.0 * se + 1e-5 * expected.abs().max(1.0),
        "{label}: {m} ± {se}, expected {expected}"
    );
}

const SKY: &str = r#"<emitter type="constant"><rgb name="radiance" value="0.8"/></emitter>"#;
/// A diffuse unit sphere filling the view from z = 5: in a constant sky L it shows ρL.
const DIFFUSE_BALL: &str =
    r#"<shape type="sphere"><bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>"#;
/// A null sphere around the origin: every camera ray crosses it twice.
const NULL_BALL: &str = r#"<shape type="sphere"><float name="radius" value="2"/><bsdf type="null"/></shape>"#;

fn path(params: &str) -> String {
    format!(r#"<integrator type="path">{params}</integrator>"#)
}

#[test]
fn max_depth_counts_the_camera_vertex_and_hide_emitters_hides_only_what_the_camera_sees() {
    let ball = format!("{SKY}{DIFFUSE_BALL}");
    assert_mean("unbounded depth", &pixels(&scene(&path(""), 5.0, &ball), 16, 1), 0.4);
    // One vertex is the camera's: only emitters seen directly, and the ball emits nothing.
    let p = pixels(&scene(&path(r#"<integer name="max_depth" value="1"/>"#), 5.0, &ball), 4, 1);
    assert!(p.iter().all(|&x| x == 0.0), "max_depth 1 shows the ball lit: {p:?}");
    // Hidden from the camera, the sky still lights the ball.
    let hide = path(r#"<boolean name="hide_emitters" value="true"/>"#);
    assert_mean("hide_emitters", &pixels(&scene(&hide, 5.0, &ball), 16, 1), 0.4);
    let p = pixels(&scene(&hide, 5.0, SKY), 4, 1);
    assert!(p.iter().all(|&x| x == 0.0), "hide_emitters shows the sky: {p:?}");
}

#[test]
fn each_pass_through_a_null_surface_costs_a_depth_and_keeps_the_sky_hidden() {
    let body = format!("{SKY}{NULL_BALL}");
    let at_depth =
        |d: i32| pixels(&scene(&path(&format!(r#"<integer name="max_depth" value="{d}"/>"#)), 5.0, &body), 4, 1);
    // Camera, entry, exit: the sky is the fourth vertex.
    assert!(at_depth(2).iter().all(|&x| x == 0.0));
    assert!(at_depth(3).iter().all(|&x| (x - 0.8).abs() < 1e-6), "{:?}", at_depth(3));
    let p = pixels(&scene(&path(r#"<boolean name="hide_emitters" value="true"/>"#), 5.0, &body), 4, 1);
    assert!(p.iter().all(|&x| x == 0.0), "the sky shows through null surfaces: {p:?}");
}

/// A diffuse plane of albedo 0.5 at z = 0 seen from z = 1.5, lit from z = 2 by `light`, rendered
/// by `direct` with `n` emitter samples.
fn lit_plane(light: &str, n: u32, seed: u64) -> Vec<f64> {
    let integrator = format!(
        r#"<integrator type="direct"><integer name="emitter_samples" value="{n}"/><integer name="bsdf_samples" value="1"/></integrator>"#
    );
    let plane = r#"<shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>"#;
    pixels(&scene(&integrator, 1.5, &format!("{light}{plane}")), 16, seed)
}

#[test]
fn direct_adds_a_delta_light_once_per_emitter_sample_and_averages_area_light_samples() {
    // The point light: L = ρ/π · I cosθ / d², ρ/π · I / 4 below it; over the view (|x|, |y| <
    // 0.13) cosθ/d² averages 0.4 % below its value at the centre.
    let point =
        r#"<emitter type="point"><point name="position" value="0, 0, 2"/><rgb name="intensity" value="4"/></emitter>"#;
    let below = 0.5 / std::f64::consts::PI * 4.0 / 4.0;
    for (n, scale) in [(1, 1.0), (4, 4.0)] {
        let (m, _) = mean_se(&lit_plane(point, n, 3));
        assert!(
            m <= scale * below && m >= scale * below * 0.993,
            "emitter_samples {n}: {m}, expected ≈ {}",
            scale * below
        );
    }
    // A downward disk light (radius 1, 2 above, L = 1): E = π r²/(r² + h²) at the centre. Pixel
    // by pixel, 1 and 4 light samples estimate the same radiance.
    let disk = r#"<shape type="disk"><transform name="to_world"><rotate x="1" angle="180"/><translate z="2"/></transform>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#;
    let (one, four) = (lit_plane(disk, 1, 5), lit_plane(disk, 4, 6));
    let diff: Vec<f64> = one.iter().zip(&four).map(|(a, b)| a - b).collect();
    assert_mean("1 − 4 area-light samples", &diff, 0.0);
    let (m, se) = mean_se(&four);
    let centre = 0.5 / 5.0;
    assert!(m <= centre + 4.0 * se && m >= centre * 0.98 - 4.0 * se, "disk light: {m} ± {se}, expected ≈ {centre}");
}
