//! The scene language as a whole, one small test per feature: includes, paths, aliases and
//! references, defaults, version upgrades, spectra, transforms, textures and their wrap modes,
//! serialized meshes, instances, Mitsuba's tangent frames, cameras, and bad input (a missing
//! include, an include cycle, a corrupt texture, a truncated mesh file), each an error that
//! names the file. Reference numbers are Mitsuba 3.9.1's (scalar_rgb).

#![allow(clippy::excessive_precision)] // Mitsuba's reference numbers, as it prints them

use glam::{Vec2, Vec3};
use radiometry::Rgb;
use render::camera::Projection;
use render::light::Light;
use render::material::Material;
use render::scene::SurfaceInteraction;
use render::shape::Geometry;
use render::xml::{load_scene, load_scene_str, LoadedScene, XmlError};
use render::{Integrator, Shape};
use std::path::{Path, PathBuf};

/// A fresh temporary directory for this test.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gonio-lang-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

const CAMERA: &str = r#"<sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="6"/></film>
    </sensor>"#;

/// A scene around `body` with a small camera.
fn scene(body: &str) -> String {
    format!("<scene version=\"3.0.0\">\n{CAMERA}\n{body}\n</scene>")
}

fn load(text: &str) -> Result<LoadedScene, XmlError> {
    load_scene_str(text, Path::new("."), &[])
}

/// A surface point with an aligned frame, for looking at a material's model.
fn at(uv: Vec2) -> SurfaceInteraction {
    SurfaceInteraction {
        t: 1.0,
        p: Vec3::ZERO,
        ng: Vec3::Z,
        frame: radiometry::Frame::IDENTITY,
        uv,
        dp_du: Vec3::X,
        dp_dv: Vec3::Y,
        shape: 0,
    }
}

/// A Lambert shape's albedo at `uv`.
fn albedo(s: &Shape, uv: Vec2) -> Rgb {
    s.material.with(&at(uv), |b| b.eval(Vec3::Z, Vec3::Z) * std::f32::consts::PI)
}

fn close(a: Rgb, b: [f32; 3], tol: f32) -> bool {
    (0..3).all(|c| (a.0[c] - b[c]).abs() <= tol * b[c].abs().max(1e-3))
}

#[test]
fn includes_nest_splice_and_resolve_files_next_to_the_includer_then_the_scene() {
    let d = temp_dir("include");
    std::fs::create_dir_all(d.join("parts/deeper")).unwrap();
    std::fs::create_dir_all(d.join("meshes")).unwrap();
    std::fs::write(d.join("meshes/tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(
        d.join("parts/a.xml"),
        r#"<scene version="3.0.0">
    <default name="r" value="0.25"/>
    <bsdf type="diffuse" id="grey"><rgb name="reflectance" value="0.3"/></bsdf>
    <include filename="deeper/b.xml"/>
</scene>"#,
    )
    .unwrap();
    // A non-scene root becomes one child, named by the include.
    std::fs::write(
        d.join("parts/deeper/b.xml"),
        r#"<scene version="3.0.0"><shape type="obj"><string name="filename" value="meshes/tri.obj"/><ref id="grey"/></shape></scene>"#,
    )
    .unwrap();
    std::fs::write(
        d.join("parts/red.xml"),
        r#"<bsdf version="3.0.0" type="diffuse"><rgb name="reflectance" value="0.8, 0.1, 0.1"/></bsdf>"#,
    )
    .unwrap();
    let main = scene(
        r#"<include filename="parts/a.xml"/>
    <shape type="sphere"><float name="radius" value="$r"/><include filename="parts/red.xml"/></shape>"#,
    );
    std::fs::write(d.join("main.xml"), &main).unwrap();
    let s = load_scene(&d.join("main.xml"), &[]).unwrap();
    let sh = s.scene.shapes();
    assert_eq!(sh.len(), 2);
    assert!(
        matches!(&sh[0].geometry, Geometry::Mesh(m) if m.len() == 1),
        "the mesh named in deeper/b.xml, found next to main.xml"
    );
    assert!(close(albedo(&sh[0], Vec2::ZERO), [0.3; 3], 1e-6));
    assert!(matches!(&sh[1].geometry, Geometry::Sphere(sp) if sp.radius == 0.25), "a default from the included file");
    assert!(close(albedo(&sh[1], Vec2::ZERO), [0.8, 0.1, 0.1], 1e-6));

    // A missing include and a cycle: each names the including file and its line.
    let missing = scene(r#"<include filename="parts/nope.xml"/>"#);
    std::fs::write(d.join("missing.xml"), &missing).unwrap();
    let e = load_scene(&d.join("missing.xml"), &[]).unwrap_err().to_string();
    let line = missing.lines().position(|l| l.contains("nope.xml")).unwrap() + 1;
    assert!(e.contains(&format!("missing.xml:{line}:")) && e.contains("nope.xml") && e.contains("not found"), "{e}");
    std::fs::write(d.join("parts/loop1.xml"), r#"<scene version="3.0.0"><include filename="loop2.xml"/></scene>"#)
        .unwrap();
    std::fs::write(d.join("parts/loop2.xml"), r#"<scene version="3.0.0"><include filename="loop1.xml"/></scene>"#)
        .unwrap();
    std::fs::write(d.join("cycle.xml"), scene(r#"<include filename="parts/loop1.xml"/>"#)).unwrap();
    let e = load_scene(&d.join("cycle.xml"), &[]).unwrap_err().to_string();
    assert!(e.contains("loop2.xml:1:") && e.contains("include cycle") && e.contains("loop1.xml → "), "{e}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn paths_aliases_refs_and_substitution() {
    let d = temp_dir("paths");
    std::fs::create_dir_all(d.join("assets")).unwrap();
    std::fs::write(d.join("assets/q.ply"), "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    let text = format!(
        r#"<scene version="2.1.0">
    <path value="assets"/>
    {CAMERA}
    <default name="kind" value="ply"/>
    <default name="prefix" value="2"/>
    <default name="pre" value="1"/>
    <shape type="$kind"><string name="filename" value="q.$kind"/>
        <bsdf type="twosided"><bsdf type="diffuse" id="deep"><float name="reflectance" value="0.$prefix$pre"/></bsdf></bsdf>
    </shape>
    <alias id="deep" as="shallow"/>
    <shape type="sphere"><ref id="shallow"/></shape>
    <shape type="sphere" id="lit\$1"><emitter type="area" id="glow"><rgb name="radiance" value="2"/></emitter></shape>
</scene>"#
    );
    let s = load_scene_str(&text, &d, &[("pre".into(), "7".into())]).unwrap();
    let sh = s.scene.shapes();
    // The longest name first ($prefix, not $pre), and -D before defaults: 0.2 then 7.
    assert!(close(albedo(&sh[1], Vec2::ZERO), [0.27; 3], 1e-6), "{:?}", albedo(&sh[1], Vec2::ZERO));
    assert!(matches!(sh[0].material, Material::TwoSided(..)));
    // An emitting shape without a BSDF is black, as in Mitsuba.
    assert_eq!(albedo(&sh[2], Vec2::ZERO), Rgb::ZERO);
    assert_eq!(s.scene.lights().len(), 1);
    // A define no attribute uses is an error.
    let e = load_scene_str(&text, &d, &[("unused".into(), "1".into())]).unwrap_err().to_string();
    assert!(e.contains("$unused") && e.contains("used nowhere"), "{e}");
    // A top-level area emitter referenced by two shapes.
    let two = scene(
        r#"<emitter type="area" id="a"><rgb name="radiance" value="1"/></emitter>
    <shape type="sphere"><ref id="a"/></shape>
    <shape type="sphere"><ref id="a"/></shape>"#,
    );
    let e = load(&two).unwrap_err().to_string();
    assert!(e.contains("already attached"), "{e}");
    // An unreferenced top-level area emitter emits nothing.
    let lone = load(&scene(r#"<emitter type="area" id="a"><rgb name="radiance" value="1"/></emitter>"#)).unwrap();
    assert!(lone.scene.lights().is_empty());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn old_versions_are_upgraded() {
    let text = format!(
        r#"<scene version="0.6.0">
    {}
    <integrator type="path"><integer name="maxDepth" value="3"/></integrator>
    <shape type="sphere">
        <bsdf type="diffuse"><texture type="checkerboard" name="diffuseReflectance">
            <float name="uscale" value="2"/><float name="vscale" value="2"/></texture></bsdf>
    </shape>
</scene>"#,
        CAMERA.replace("to_world", "toWorld")
    );
    let s = load(&text).unwrap();
    assert_eq!(s.integrator, Integrator::path(3, 5));
    // to_uv = scale(2): the cell at uv (0.3, 0.3) is (0.6, 0.6): color0 (0.4) where unscaled it would be too,
    // and (0.3, 0.1) → (0.6, 0.2): color1.
    let sh = &s.scene.shapes()[0];
    assert!(close(albedo(sh, Vec2::new(0.3, 0.1)), [0.2; 3], 1e-6));
    assert!(close(albedo(sh, Vec2::new(0.3, 0.3)), [0.4; 3], 1e-6));
    assert!(load("<scene version=\"3.0\"/>").unwrap_err().to_string().contains("X.Y.Z"));
}

#[test]
fn spectra_reduce_as_mitsubas_rgb_variants() {
    let d = temp_dir("spectra");
    std::fs::write(d.join("flat.spd"), "# a comment\n400 0.2\n700 0.4 trailing words\n").unwrap();
    let text = scene(
        r#"<shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" value="400:0.2, 700:0.4"/></bsdf></shape>
    <shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" filename="flat.spd"/></bsdf></shape>
    <shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" value="0.5"/></bsdf></shape>
    <shape type="sphere"><bsdf type="diffuse"><spectrum type="d65" name="reflectance"><rgb name="color" value="0.2, 0.5, 0.8"/></spectrum></bsdf></shape>
    <shape type="sphere"><emitter type="area"><spectrum name="radiance" value="400:0, 500:8, 600:15.6, 700:18.4"/></emitter></shape>
    <shape type="sphere"><emitter type="area"><spectrum name="radiance" value="0.5"/></emitter></shape>
    <shape type="sphere"><emitter type="area"><spectrum type="blackbody" name="radiance"><float name="temperature" value="3000"/></spectrum></emitter></shape>
    <emitter type="point"><spectrum name="intensity" value="1"/></emitter>"#,
    );
    let s = load_scene_str(&text, &d, &[]).unwrap();
    let sh = s.scene.shapes();
    let mitsuba = [0.3598981, 0.2952424, 0.2261902];
    assert!(close(albedo(&sh[0], Vec2::ZERO), mitsuba, 2e-6));
    assert!(close(albedo(&sh[1], Vec2::ZERO), mitsuba, 2e-6), "the .spd file");
    assert!(close(albedo(&sh[2], Vec2::ZERO), [0.5; 3], 1e-7));
    assert!(close(albedo(&sh[3], Vec2::ZERO), [0.2, 0.5, 0.8], 1e-7));
    let radiance = |i: usize| sh[i].emission.as_ref().and_then(|t| t.constant()).unwrap();
    assert!(close(radiance(4), [20.71084, 10.85463, 2.771152], 2e-6));
    assert!(close(radiance(5), [0.602397, 0.4741455, 0.454458], 2e-6));
    // A 3000 K blackbody is orange: R > G > B, in the ratio of its spectral colour (1.77 : 0.84 : 0.27).
    let bb = radiance(6);
    assert!(
        (bb.0[0] / bb.0[1] - 1.770615 / 0.844281).abs() < 0.01
            && (bb.0[2] / bb.0[1] - 0.272217 / 0.844281).abs() < 0.01,
        "{bb:?}"
    );
    assert!(
        matches!(&s.scene.lights()[0], Light::Point(p) if close(p.intensity, [1.204794, 0.948291, 0.9089161], 2e-6))
    );
    // A reflectance <rgb> must lie in [0, 1]; wavelengths must increase.
    let e = load(&scene(
        r#"<shape type="sphere"><bsdf type="diffuse"><rgb name="reflectance" value="1.5"/></bsdf></shape>"#,
    ))
    .unwrap_err();
    assert!(e.to_string().contains("[0, 1]"), "{e}");
    let e = load(&scene(r#"<shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" value="500:0.2, 400:0.3"/></bsdf></shape>"#)).unwrap_err();
    assert!(e.to_string().contains("increase") && e.pos.is_some(), "{e}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn textures_wrap_and_feed_any_varying_parameter() {
    let d = temp_dir("textures");
    // 2 × 2 grey texels 0, 64 / 128, 255 (raw: /255).
    let img = image::GrayImage::from_raw(2, 2, vec![0, 64, 128, 255]).unwrap();
    img.save(d.join("g.png")).unwrap();
    let tex = |extra: &str| {
        format!(
            r#"<texture type="bitmap" name="reflectance"><string name="filename" value="g.png"/><boolean name="raw" value="true"/>{extra}</texture>"#
        )
    };
    let text = scene(&format!(
        r#"<shape type="sphere"><bsdf type="diffuse">{}</bsdf></shape>
    <shape type="sphere"><bsdf type="diffuse">{}</bsdf></shape>
    <shape type="sphere"><bsdf type="diffuse">{}</bsdf></shape>
    <shape type="sphere"><bsdf type="ward"><texture type="bitmap" name="alpha"><string name="filename" value="g.png"/></texture></bsdf></shape>"#,
        tex(r#"<string name="filter_type" value="nearest"/>"#),
        tex(r#"<string name="wrap_mode" value="clamp"/>"#),
        tex(r#"<string name="wrap_mode" value="mirror"/><string name="filter_type" value="nearest"/>"#),
    ));
    let s = load_scene_str(&text, &d, &[]).unwrap();
    let sh = s.scene.shapes();
    let v = |i: usize, u: f32, w: f32| albedo(&sh[i], Vec2::new(u, w)).0[0];
    // Row 0 is the top of the image at v ∈ [0, ½).
    assert_eq!((v(0, 0.25, 0.25), v(0, 0.75, 0.25), v(0, 0.25, 0.75)), (0.0, 64.0 / 255.0, 128.0 / 255.0));
    assert_eq!(v(0, 1.25, 0.25), 0.0, "nearest repeats");
    assert_eq!(v(1, 1.5, 0.25), 64.0 / 255.0, "clamp holds the edge texel");
    assert_eq!(v(2, 1.25, 0.25), 64.0 / 255.0, "mirror turns back at the edge");
    assert!(matches!(sh[3].material, Material::Textured(_)), "a gonio model's parameter takes a texture too");
    // A parameter that cannot vary, a corrupt image.
    let e = load_scene_str(
        &scene(&format!(
            r#"<shape type="sphere"><bsdf type="roughplastic">{}</bsdf></shape>"#,
            tex("").replace("reflectance", "alpha")
        )),
        &d,
        &[],
    )
    .unwrap_err();
    assert!(e.to_string().contains("cannot be a texture"), "{e}");
    std::fs::write(d.join("bad.png"), b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let e = load_scene_str(
        &scene(&tex("").replace("g.png", "bad.png").replace("name=\"reflectance\"", "id=\"t\"")),
        &d,
        &[],
    )
    .unwrap_err();
    let m = e.to_string();
    assert!(m.contains("bad.png") && m.contains("decode") && e.pos.is_some(), "{m}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn serialized_meshes_and_instances() {
    let d = temp_dir("serialized");
    let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let uv = [Vec2::ZERO, Vec2::X, Vec2::Y];
    let q = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    let bytes = render::io::serialized::write(&[
        (&p, None, Some(&uv), &[[0, 1, 2]]),
        (&q, None, None, &[[0, 1, 2], [0, 2, 3]]),
    ]);
    std::fs::write(d.join("m.serialized"), &bytes).unwrap();
    std::fs::write(d.join("cut.serialized"), &bytes[..40]).unwrap();
    let text = scene(
        r#"<shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shape_index" value="1"/></shape>
    <shape type="shapegroup" id="g">
        <shape type="serialized"><string name="filename" value="m.serialized"/></shape>
        <shape type="sphere"><float name="radius" value="0.5"/></shape>
    </shape>
    <shape type="instance"><ref id="g"/><transform name="to_world"><translate x="3"/></transform></shape>
    <shape type="instance"><ref id="g"/><transform name="to_world"><scale value="2"/></transform></shape>"#,
    );
    let s = load_scene_str(&text, &d, &[]).unwrap();
    let sh = s.scene.shapes();
    assert_eq!(sh.len(), 5, "the mesh, and two instances of a group of two; the group itself is not rendered");
    assert!(matches!(&sh[0].geometry, Geometry::Mesh(m) if m.len() == 2));
    assert!(
        matches!(&sh[1].geometry, Geometry::Mesh(m) if m.positions[1] == Vec3::new(4.0, 0.0, 0.0) && m.uvs.is_some())
    );
    assert!(matches!(&sh[2].geometry, Geometry::Sphere(sp) if sp.center == Vec3::new(3.0, 0.0, 0.0)));
    assert!(matches!(&sh[4].geometry, Geometry::Sphere(sp) if sp.radius == 1.0));
    // A truncated file and a mesh index past the end: errors naming the file and the line.
    for (file, index, words) in [("cut.serialized", 0, "cut.serialized"), ("m.serialized", 5, "out of range")] {
        let t = scene(&format!(
            r#"<shape type="serialized"><string name="filename" value="{file}"/><integer name="shape_index" value="{index}"/></shape>"#
        ));
        let e = load_scene_str(&t, &d, &[]).unwrap_err();
        assert!(e.to_string().contains(words) && e.pos.is_some(), "{e}");
    }
    std::fs::remove_dir_all(&d).unwrap();
}

/// The hit of the scene's only shape along a ray.
fn hit(s: &LoadedScene, o: Vec3, d: Vec3) -> SurfaceInteraction {
    s.scene.intersect(&render::ray::Ray::new(o, d)).expect("a hit")
}

#[test]
fn sphere_and_mesh_frames_are_mitsubas() {
    // Mitsuba 3.9.1: a sphere of centre (1, 2, 3) and radius 2, hit from (10, 2.5, 3.5) along −x.
    let s = load(&scene(
        r#"<shape type="sphere"><point name="center" x="1" y="2" z="3"/><float name="radius" value="2"/></shape>"#,
    ))
    .unwrap();
    let h = hit(&s, Vec3::new(10.0, 2.5, 3.5), -Vec3::X);
    assert!((h.uv - Vec2::new(0.0415645018, 0.419569403)).length() < 1e-6, "{}", h.uv);
    assert!(h.dp_du.abs_diff_eq(Vec3::new(-3.1415925, 11.7547636, 0.0), 1e-4), "{}", h.dp_du);
    assert!(h.dp_dv.abs_diff_eq(Vec3::new(1.51753354, 0.405577838, -6.08366823), 1e-4), "{}", h.dp_dv);
    assert!(h.frame.s.abs_diff_eq(Vec3::new(-0.258198887, 0.966091812, 0.0), 1e-6));
    assert!(h.frame.t.abs_diff_eq(Vec3::new(-0.241522983, -0.0645497218, 0.968245983), 1e-6));
    // Turned 90° about z (and scaled): u moves by a quarter turn, the frame stays.
    let s = load(&scene(
        r#"<shape type="sphere"><transform name="to_world"><scale value="2"/><rotate z="1" angle="90"/><translate x="1" y="2" z="3"/></transform></shape>"#,
    ))
    .unwrap();
    let h = hit(&s, Vec3::new(10.0, 2.5, 3.5), -Vec3::X);
    assert!((h.uv - Vec2::new(0.791564465, 0.419569403)).length() < 1e-6, "{}", h.uv);
    assert!(h.frame.s.abs_diff_eq(Vec3::new(-0.258198887, 0.966091812, 0.0), 1e-6));

    // Mitsuba's test quad (uvs and vertex normals; OBJ flips v): hit B at (1.5, 0.5).
    let d = temp_dir("frames");
    std::fs::write(
        d.join("q.obj"),
        "v 0 0 0\nv 2 0 0\nv 2 2 0.4\nv 0 2 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nvn 0.2 0 1\nvn 0.2 0.2 1\nvn 0 0.2 1\nf 1/1/1 2/2/2 3/3/3 4/4/4\n",
    )
    .unwrap();
    let s = load_scene_str(&scene(r#"<shape type="obj"><string name="filename" value="q.obj"/></shape>"#), &d, &[])
        .unwrap();
    let h = hit(&s, Vec3::new(1.5, 0.5, 5.0), -Vec3::Z);
    assert!((h.uv - Vec2::new(0.75, 0.75)).length() < 1e-6, "{}", h.uv);
    assert!(h.frame.n.abs_diff_eq(Vec3::new(0.147223085, 0.0484589562, 0.987915576), 1e-6));
    assert!(h.frame.s.abs_diff_eq(Vec3::new(0.989103317, -0.00721287308, -0.147046298), 1e-6));
    // Without normals Mitsuba smooths them by angle; without uvs ∂p/∂u is the first edge.
    std::fs::write(d.join("n.obj"), "v 0 0 0\nv 2 0 0\nv 2 2 0.4\nv 0 2 0\nf 1 2 3 4\n").unwrap();
    let s = load_scene_str(&scene(r#"<shape type="obj"><string name="filename" value="n.obj"/></shape>"#), &d, &[])
        .unwrap();
    let h = hit(&s, Vec3::new(1.5, 0.5, 5.0), -Vec3::Z);
    assert!(h.frame.n.abs_diff_eq(Vec3::new(-0.0496273972, -0.147923186, 0.987752974), 1e-6), "{}", h.frame.n);
    assert!((h.uv - Vec2::new(0.5, 0.25)).length() < 1e-6 && h.dp_du.abs_diff_eq(Vec3::new(2.0, 0.0, 0.0), 1e-6));
    std::fs::remove_dir_all(&d).unwrap();

    // A rectangle under a mirroring matrix: geometric and shading normals point apart, as in Mitsuba.
    let s = load(&scene(r#"<shape type="rectangle"><transform name="to_world"><scale x="-1"/></transform></shape>"#))
        .unwrap();
    let h = hit(&s, Vec3::new(0.3, 0.2, 2.0), -Vec3::Z);
    assert!((h.uv - Vec2::new(0.35, 0.6)).length() < 1e-6 && h.ng == -Vec3::Z && h.frame.n == Vec3::Z);
    assert!(h.frame.s.abs_diff_eq(-Vec3::X, 1e-6));
}

#[test]
fn cameras_match_mitsubas_rays() {
    let cam = |body: &str, film: &str| {
        let text = format!(
            r#"<scene version="3.0.0"><sensor type="{body}<film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="48"/>{film}</film></sensor></scene>"#
        );
        load(&text).unwrap().scene.camera
    };
    let look = r#"<transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>"#;
    // Thin lens, radius 0.5 focused at 4: Mitsuba's rays for film position (0, 0), lens sample (1, 0.5).
    let c = cam(
        &format!(
            r#"thinlens"><float name="fov" value="90"/><float name="aperture_radius" value="0.5"/><float name="focus_distance" value="4"/>{look}"#
        ),
        "",
    );
    assert!(matches!(c.projection, Projection::ThinLens { .. }));
    let r = c.ray(Vec2::ZERO, Vec2::new(1.0, 0.5));
    assert!(r.o.abs_diff_eq(Vec3::new(-0.50875002, 0.0075000012, 4.99), 1e-5), "{}", r.o);
    assert!(r.d.abs_diff_eq(Vec3::new(-0.57346237, 0.49153921, -0.65538549), 1e-5), "{}", r.d);
    let r = c.ray(Vec2::new(16.0, 36.0), Vec2::new(0.9, 0.3));
    assert!(r.d.abs_diff_eq(Vec3::new(-0.36034703, -0.29768541, -0.88404381), 1e-5), "{}", r.d);
    // The default 50 mm lens on a 4:3 film.
    let c = cam(r#"perspective">"#, "");
    assert!(c.ray(Vec2::ZERO, Vec2::splat(0.5)).d.abs_diff_eq(Vec3::new(0.31767344, 0.23825508, 0.91777885), 1e-5));
    // A crop window: its first pixel is the film's (16, 8) pixel.
    let c = cam(
        r#"perspective"><float name="fov" value="90"/>"#,
        r#"<integer name="crop_offset_x" value="16"/><integer name="crop_offset_y" value="8"/><integer name="crop_width" value="32"/><integer name="crop_height" value="24"/>"#,
    );
    assert_eq!((c.width, c.height), (32, 24));
    assert!(c.ray(Vec2::ZERO, Vec2::splat(0.5)).d.abs_diff_eq(Vec3::new(0.40824831, 0.40824831, 0.81649655), 1e-5));
    // Orthographic: to_world's scale sets the extent.
    let c = cam(
        r#"orthographic"><transform name="to_world"><scale x="2" y="3"/><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>"#,
        "",
    );
    let r = c.ray(Vec2::new(16.0, 36.0), Vec2::splat(0.5));
    assert!(r.o.abs_diff_eq(Vec3::new(-1.0, -1.125, 4.99), 1e-5) && r.d.abs_diff_eq(-Vec3::Z, 1e-6), "{:?}", r);
}
