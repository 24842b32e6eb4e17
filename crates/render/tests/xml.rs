//! Mitsuba 3 XML scenes: every supported element parsed into the expected scene, the four
//! shared benchmark scenes (when /work/shared/bench is present, and always as embedded
//! copies), and bad files that must each give an error naming the line and the element.

use glam::{Mat4, Vec3};
use radiometry::Rgb;
use render::filter::Filter;
use render::light::Light;
use render::shape::Geometry;
use render::xml::{load_scene, load_scene_str, LoadedScene, XmlError};
use render::{render, Integrator, RenderOptions};
use std::path::{Path, PathBuf};

fn bench_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/bench")
}

/// A fresh temporary directory for this test.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gonio-xml-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn load(text: &str) -> Result<LoadedScene, XmlError> {
    load_scene_str(text, Path::new("."), &[])
}

/// A scene around `body` with a small camera.
fn scene(body: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="6"/></film>
    </sensor>
{body}
</scene>"#
    )
}

/// The 1-based line of the first occurrence of `needle` in `text`.
fn line_of(text: &str, needle: &str) -> usize {
    let i = text.find(needle).unwrap_or_else(|| panic!("'{needle}' not in the text"));
    text[..i].matches('\n').count() + 1
}

/// Loads `text`, expects an error, and checks that it names the line of `at` and `element`
/// and contains every one of `words`.
fn expect_error(text: &str, at: &str, element: &str, words: &[&str]) -> String {
    let e = load(text).expect_err("this scene must not load");
    let msg = e.to_string();
    let line = line_of(text, at);
    assert_eq!(e.pos.map(|p| p.line as usize), Some(line), "wrong line in: {msg}");
    assert!(msg.contains(&format!(":{line}:")), "no line in: {msg}");
    assert!(msg.contains(element), "no element '{element}' in: {msg}");
    for w in words {
        assert!(msg.contains(w), "no '{w}' in: {msg}");
    }
    msg
}

fn sphere(g: &Geometry) -> render::shape::Sphere {
    match g {
        Geometry::Sphere(s) => *s,
        other => panic!("not a sphere: {other:?}"),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

/// A direction pair for comparing models.
fn dirs() -> (Vec3, Vec3) {
    (Vec3::new(0.3, -0.2, 0.9).normalize(), Vec3::new(-0.25, 0.1, 0.95).normalize())
}

/// A surface point with an aligned frame at uv (0.5, 0.5), for looking at a material's model.
fn probe() -> render::scene::SurfaceInteraction {
    render::scene::SurfaceInteraction {
        t: 1.0,
        p: Vec3::ZERO,
        ng: Vec3::Z,
        frame: radiometry::Frame::IDENTITY,
        uv: glam::Vec2::splat(0.5),
        dp_du: Vec3::X,
        dp_dv: Vec3::Y,
        shape: 0,
    }
}

fn same_model(a: &dyn brdf::Brdf, b: &dyn brdf::Brdf) {
    let (wi, wo) = dirs();
    let (x, y) = (a.eval(wi, wo), b.eval(wi, wo));
    assert!((x - y).max_channel().abs() <= 1e-6 * y.max_channel().max(1.0), "{x:?} vs {y:?}");
}

// ---------------------------------------------------------------------------------------
// The shared scenes.

const SPHERES: &str = include_str!("data/spheres.xml");
const FURNACE: &str = include_str!("data/furnace.xml");

#[test]
fn shared_scenes_load_when_present() {
    let dir = bench_dir().join("scenes");
    if !dir.exists() {
        eprintln!("skipping: {} is absent", dir.display());
        return;
    }
    for (name, shapes, lights, depth) in
        [("spheres", 5, 2, 8), ("furnace", 1, 1, 1000), ("envmap", 1, 1, 8), ("mesh", 1, 1, 8)]
    {
        let s = load_scene(&dir.join(format!("{name}.xml")), &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((s.width, s.height, s.spp, s.seed), (512, 512, 64, 0), "{name}");
        assert_eq!(s.integrator, Integrator::path(depth, 5), "{name}");
        assert_eq!(s.filter, Filter::Box, "{name}");
        assert_eq!(s.scene.shapes().len(), shapes, "{name}");
        assert_eq!(s.scene.lights().len(), lights, "{name}");
        if name == "mesh" {
            assert_eq!(s.scene.primitive_count(), 100_000);
        }
        if name == "envmap" || name == "mesh" {
            assert!(matches!(s.scene.lights()[0], Light::EnvMap(_)), "{name}");
        }
    }
    // The embedded copies are the shared files (so that the always-run tests below test them).
    for (name, copy) in [("spheres", SPHERES), ("furnace", FURNACE)] {
        let shared = std::fs::read_to_string(dir.join(format!("{name}.xml"))).unwrap();
        assert_eq!(shared.trim(), copy.trim(), "tests/data/{name}.xml differs from the shared scene");
    }
}

#[test]
fn embedded_spheres_scene_matches_its_description() {
    let s = load(SPHERES).unwrap();
    assert_eq!((s.width, s.height, s.spp), (512, 512, 64));
    assert!(close(s.scene.camera.origin(), Vec3::new(0.0, 3.5, 11.5)));
    assert_eq!(s.scene.camera.near_clip, 0.01);
    let shapes = s.scene.shapes();
    match &shapes[0].geometry {
        Geometry::Rectangle(r) => {
            assert!(close(r.n, Vec3::Y), "floor normal {:?}", r.n);
            assert!((r.area() - 400.0).abs() < 1e-3);
        }
        other => panic!("floor is {other:?}"),
    }
    for (i, x) in [-3.3, -1.1, 1.1, 3.3].into_iter().enumerate() {
        let sp = sphere(&shapes[i + 1].geometry);
        assert!(close(sp.center, Vec3::new(x, 1.0, 0.0)) && sp.radius == 1.0);
    }
    let diffuse = brdf::build("lambert", &[("albedo", "0.5")]).unwrap();
    same_model(shapes[0].material.fixed().unwrap(), &*diffuse);
    same_model(shapes[1].material.fixed().unwrap(), &*diffuse);
    let au = brdf::build(
        "microfacet",
        &[("distribution", "beckmann"), ("alpha", "0.1"), ("material", "Au"), ("shadowing", "smith-separable")],
    )
    .unwrap();
    same_model(shapes[2].material.fixed().unwrap(), &*au);
    let cu = brdf::build(
        "microfacet",
        &[("distribution", "ggx"), ("alpha", "0.3"), ("material", "Cu"), ("shadowing", "smith-separable")],
    )
    .unwrap();
    same_model(shapes[3].material.fixed().unwrap(), &*cu);
    // Mitsuba's roughplastic, by the same name and parameters.
    let plastic = brdf::build(
        "roughplastic",
        &[
            ("distribution", "ggx"),
            ("alpha", "0.1"),
            ("int_ior", "1.5"),
            ("ext_ior", "1"),
            ("diffuse_reflectance", "0.1,0.27,0.6"),
        ],
    )
    .unwrap();
    same_model(shapes[4].material.fixed().unwrap(), &*plastic);
    let lights = s.scene.lights();
    assert!(matches!(lights[0], Light::Constant(c) if c.radiance == Rgb::ONE));
    match &lights[1] {
        Light::Point(p) => {
            assert!(close(p.position, Vec3::new(3.0, 7.0, 4.0)) && p.intensity == Rgb::splat(150.0));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn embedded_furnace_renders_white() {
    // The shared furnace at 8×8 and 16 spp: every pixel's expectation is 1.
    let text = FURNACE.replace(r#"value="512""#, r#"value="8""#);
    let s = load(&text).unwrap();
    assert_eq!((s.width, s.height), (8, 8));
    let img = render(
        &s.scene,
        &RenderOptions { spp: 16, seed: s.seed, threads: 2, integrator: s.integrator, ..Default::default() },
        |_| {},
    );
    let v: Vec<f64> = img.pixels.iter().map(|p| p.0[1] as f64).collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    // 4σ of the mean of the pixel estimates, plus f32 rounding.
    assert!((mean - 1.0).abs() <= 4.0 * (var / n).sqrt() + 1e-4, "mean {mean}, σ {}", (var / n).sqrt());
}

// ---------------------------------------------------------------------------------------
// Every supported element.

#[test]
fn transforms_place_shapes() {
    let s = load(&scene(
        r#"
    <shape type="sphere">
        <point name="center" value="1, 0, 0"/>
        <float name="radius" value="0.5"/>
        <transform name="to_world">
            <scale value="2"/>
            <rotate y="1" angle="90"/>
            <translate x="0" y="1" z="0"/>
        </transform>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><matrix value="1 0 0 0  0 0 1 0  0 -1 0 0  0 0 0 1"/></transform>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><matrix value="2 0 0  0 3 0  0 0 1"/><translate value="0 0 -5"/></transform>
    </shape>"#,
    ))
    .unwrap();
    let sp = sphere(&s.scene.shapes()[0].geometry);
    // (1,0,0) → scaled (2,0,0) → rotated 90° about y: (0,0,−2) → translated (0,1,−2).
    assert!(close(sp.center, Vec3::new(0.0, 1.0, -2.0)), "{:?}", sp.center);
    assert!((sp.radius - 1.0).abs() < 1e-6);
    let Geometry::Rectangle(r) = &s.scene.shapes()[1].geometry else { panic!() };
    assert!(close(r.n, Vec3::Y));
    let Geometry::Rectangle(r) = &s.scene.shapes()[2].geometry else { panic!() };
    assert!(close(r.center, Vec3::new(0.0, 0.0, -5.0)) && (r.area() - 24.0).abs() < 1e-4);
    // Non-uniform scaling cannot stay a sphere.
    let bad =
        scene(r#"<shape type="sphere"><transform name="to_world"><scale x="1" y="2" z="1"/></transform></shape>"#);
    expect_error(&bad, "<scale x", "to_world", &["uniformly"]);
}

#[test]
fn sensor_film_sampler_and_integrators() {
    let text = r#"<scene version="3.0.0">
    <integrator type="direct"/>
    <sensor type="perspective">
        <float name="fov" value="60"/>
        <string name="fov_axis" value="y"/>
        <float name="near_clip" value="0.5"/>
        <float name="far_clip" value="50"/>
        <transform name="to_world"><translate x="1" y="2" z="3"/></transform>
        <sampler type="stratified"><integer name="sample_count" value="9"/><integer name="seed" value="7"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="20"/><integer name="height" value="10"/>
            <rfilter type="gaussian"><float name="stddev" value="0.25"/></rfilter>
        </film>
    </sensor>
</scene>"#;
    let s = load(text).unwrap();
    assert_eq!((s.width, s.height, s.spp, s.seed), (20, 10, 9, 7));
    assert_eq!(s.integrator, Integrator::DIRECT);
    assert!(matches!(&s.filter, Filter::Gaussian(g) if g.stddev == 0.25 && g.radius == 1.0));
    let cam = &s.scene.camera;
    assert!(close(cam.origin(), Vec3::new(1.0, 2.0, 3.0)));
    assert_eq!((cam.near_clip, cam.far_clip, cam.width, cam.height), (0.5, 50.0, 20, 10));
    // fov 60° along y: the top edge's ray is 30° above the axis (camera looks along +z).
    let top = cam.ray(glam::Vec2::new(10.0, 0.0), glam::Vec2::splat(0.5));
    assert!((top.d.y / top.d.z - 30f32.to_radians().tan()).abs() < 1e-5, "{:?}", top.d);
    // Mitsuba's defaults: path with unbounded depth, 4 spp, a gaussian filter of σ = 0.5.
    let d = load(&scene("")).unwrap();
    assert_eq!(d.integrator, Integrator::path(u32::MAX, 5));
    assert_eq!(d.spp, 4);
    assert!(matches!(&d.filter, Filter::Gaussian(g) if g.stddev == 0.5 && g.radius == 2.0));
    let p = load(&scene(r#"<integrator type="phong"><boolean name="shadows" value="false"/></integrator>"#)).unwrap();
    assert_eq!(p.integrator, Integrator::Phong { shadows: false });
    let p = load(&scene(r#"<integrator type="path"><integer name="max_depth" value="3"/></integrator>"#)).unwrap();
    assert_eq!(p.integrator, Integrator::path(3, 5));
}

#[test]
fn bsdfs_by_mitsuba_and_gonio_names_refs_and_twosided() {
    let s = load(&scene(
        r#"
    <bsdf type="ward" id="w">
        <rgb name="ks" value="0.3, 0.2, 0.1"/>
        <float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.3"/>
        <spectrum name="diffuse" value="0.2"/>
    </bsdf>
    <shape type="sphere"><ref id="w"/></shape>
    <shape type="sphere"><bsdf type="twosided"><bsdf type="diffuse"><float name="reflectance" value="0.25"/></bsdf></bsdf></shape>
    <shape type="sphere"><bsdf type="conductor"><string name="material" value="Au"/></bsdf></shape>
    <shape type="sphere"><bsdf type="conductor"/></shape>
    <shape type="sphere">
        <bsdf type="roughconductor">
            <rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3, 2.5, 2"/>
            <float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.2"/>
            <string name="distribution" value="ggx"/>
        </bsdf>
    </shape>
    <shape type="sphere"><bsdf type="plastic"><string name="int_ior" value="bk7"/></bsdf></shape>
    <shape type="sphere"/>
    <shape type="sphere"><bsdf type="phong"><float name="ke" value="30"/></bsdf></shape>"#,
    ))
    .unwrap();
    let sh = s.scene.shapes();
    let ward =
        brdf::build("ward", &[("ks", "0.3,0.2,0.1"), ("alpha_u", "0.1"), ("alpha_v", "0.3"), ("diffuse", "0.2")])
            .unwrap();
    same_model(sh[0].material.fixed().unwrap(), &*ward);
    sh[1].material.with(&probe(), |m| {
        same_model(m, &*brdf::build("lambert", &[("albedo", "0.25")]).unwrap());
        assert!(m.back_side());
    });
    let (_, wo) = dirs();
    let gold = brdf::build("mirror", &[("fresnel", "conductor"), ("material", "Au")]).unwrap();
    let (a, b) = (
        sh[2].material.fixed().unwrap().sample(wo, 0.5, glam::Vec2::splat(0.5)).unwrap(),
        gold.sample(wo, 0.5, glam::Vec2::splat(0.5)).unwrap(),
    );
    assert!(a.delta && a.weight == b.weight);
    let perfect = sh[3].material.fixed().unwrap().sample(wo, 0.5, glam::Vec2::splat(0.5)).unwrap();
    assert_eq!(perfect.weight, Rgb::ONE, "material none is a perfect mirror");
    let custom = brdf::build(
        "microfacet",
        &[
            ("fresnel", "conductor"),
            ("eta", "0.2,0.9,1.1"),
            ("k", "3,2.5,2"),
            ("alpha_u", "0.05"),
            ("alpha_v", "0.2"),
            ("shadowing", "smith-separable"),
        ],
    )
    .unwrap();
    same_model(sh[4].material.fixed().unwrap(), &*custom);
    // Smooth plastic: ρ_d = 0.5 by default; the named index bk7 becomes 1.5046 and air 1.000277.
    let smooth = brdf::build("plastic", &[("int_ior", "1.5046"), ("ext_ior", "1.000277")]).unwrap();
    same_model(sh[5].material.fixed().unwrap(), &*smooth);
    assert!(sh[5].material.fixed().unwrap().has_delta());
    same_model(sh[6].material.fixed().unwrap(), &*brdf::build("lambert", &[("albedo", "0.5")]).unwrap());
    same_model(sh[7].material.fixed().unwrap(), &*brdf::build("phong", &[("ke", "30")]).unwrap());
}

#[test]
fn emitters_meshes_and_params() {
    let dir = temp_dir("elements");
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(
        dir.join("tri.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n2 0 0\n0 2 0\n3 0 1 2\n",
    )
    .unwrap();
    let mut env = render::Image::new(4, 2);
    env.pixels.iter_mut().for_each(|p| *p = Rgb::splat(2.0));
    env.save(dir.join("env.exr")).unwrap();
    let text = scene(
        r#"
    <default name="r" value="0.75"/>
    <default name="mesh" value="tri"/>
    <emitter type="envmap">
        <string name="filename" value="env.exr"/>
        <float name="scale" value="0.5"/>
    </emitter>
    <emitter type="point">
        <transform name="to_world"><translate x="1" y="2" z="3"/></transform>
        <rgb name="intensity" value="5"/>
    </emitter>
    <shape type="obj">
        <string name="filename" value="$mesh.obj"/>
        <transform name="to_world"><translate z="1"/></transform>
    </shape>
    <shape type="ply">
        <string name="filename" value="$mesh.ply"/>
        <boolean name="face_normals" value="true"/>
        <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter>
    </shape>
    <shape type="cube"><transform name="to_world"><scale value="0.5"/></transform></shape>
    <shape type="sphere"><float name="radius" value="$r"/></shape>"#,
    );
    let s = load_scene_str(&text, &dir, &[]).unwrap();
    let sh = s.scene.shapes();
    let Geometry::Mesh(m) = &sh[0].geometry else { panic!() };
    assert!(m.len() == 1 && (m.area() - 0.5).abs() < 1e-6 && m.positions[0].z == 1.0);
    let Geometry::Mesh(m) = &sh[1].geometry else { panic!() };
    assert!((m.area() - 2.0).abs() < 1e-6);
    assert_eq!(sh[1].emission.as_ref().and_then(|t| t.constant()), Some(Rgb::new(1.0, 2.0, 3.0)));
    let Geometry::Mesh(c) = &sh[2].geometry else { panic!() };
    assert!(c.len() == 12 && (c.area() - 6.0).abs() < 1e-5);
    assert_eq!(sphere(&sh[3].geometry).radius, 0.75);
    let lights = s.scene.lights();
    let Light::EnvMap(e) = &lights[0] else { panic!("{:?}", lights[0]) };
    assert!((e.eval(Vec3::Y) - Rgb::ONE).max_channel().abs() < 1e-6, "scale 0.5 of radiance 2");
    assert!(
        matches!(&lights[1], Light::Point(p) if close(p.position, Vec3::new(1.0, 2.0, 3.0)) && p.intensity == Rgb::splat(5.0))
    );
    assert!(matches!(&lights[2], Light::Area(a) if a.shape == 1));
    // Defines override defaults.
    let s = load_scene_str(&text, &dir, &[("r".into(), "2".into())]).unwrap();
    assert_eq!(sphere(&s.scene.shapes()[3].geometry).radius, 2.0);
    // From a file: paths resolve against the file's directory, whatever the working directory.
    std::fs::write(dir.join("scene.xml"), &text).unwrap();
    assert_eq!(load_scene(&dir.join("scene.xml"), &[]).unwrap().scene.shapes().len(), 4);
    std::fs::remove_dir_all(&dir).unwrap();
    let _ = Mat4::IDENTITY;
}

// ---------------------------------------------------------------------------------------
// Bad files: each error names the line and the element, and what is accepted.

#[test]
fn malformed_xml() {
    let text = "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n</scene>";
    let e = load(text).unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with("<string>:3:") && msg.contains("malformed XML"), "{msg}");
    let e = load_scene(Path::new("/nonexistent/scene.xml"), &[]).unwrap_err().to_string();
    assert!(e.contains("/nonexistent/scene.xml") && e.contains("cannot read"), "{e}");
    let e = load("<scena/>").unwrap_err().to_string();
    assert!(e.contains("<scena>") && e.contains("<scene>"), "{e}");
}

#[test]
fn unknown_elements_and_types() {
    let t = scene(r#"<medium type="homogeneous"/>"#);
    expect_error(&t, "<medium", "<medium", &["accepted elements", "shape", "emitter"]);
    let t = scene(r#"<shape type="sphere"><bitmap name="x"/></shape>"#);
    expect_error(&t, "<bitmap", "<bitmap", &["float", "bsdf"]);
    let t = scene(r#"<shape type="teapot"/>"#);
    expect_error(&t, "teapot", r#"<shape type="teapot">"#, &["obj, ply, serialized, sphere, rectangle"]);
    let t = scene(r#"<shape type="sphere"><bsdf type="velvet"/></shape>"#);
    expect_error(&t, "velvet", r#"<bsdf type="velvet">"#, &["roughconductor", "lambert", "ward"]);
    let t = scene(r#"<emitter type="laser"/>"#);
    expect_error(&t, "laser", r#"<emitter type="laser">"#, &["point", "constant", "envmap"]);
    let t = scene(r#"<integrator type="bdpt"/>"#);
    expect_error(&t, "bdpt", r#"<integrator type="bdpt">"#, &["path, direct, phong"]);
    let t = scene(r#"<shape type="sphere"><bsdf type="hair"/></shape>"#);
    expect_error(&t, "hair", "<bsdf", &["not supported", "roughdielectric"]);
    let t = scene(r#"<shape type="sphere"><float name="radiuss" value="1"/></shape>"#);
    expect_error(&t, "radiuss", "radiuss", &["center, radius"]);
    let t = scene(r#"<shape type="sphere" colour="red"/>"#);
    expect_error(&t, "colour", "<shape", &["type, id, name"]);
    let t = scene(r#"<shape type="cube"><transform name="to_world"><shear value="1"/></transform></shape>"#);
    expect_error(&t, "<shear", "<shear", &["translate, rotate, scale, matrix, lookat"]);
}

#[test]
fn bad_values() {
    let t = scene(r#"<shape type="sphere"><float name="radius" value="one"/></shape>"#);
    expect_error(&t, "value=\"one\"", "<float name=\"radius\">", &["\"one\"", "number"]);
    let t = scene(r#"<shape type="sphere"><integer name="radius" value="1.5"/></shape>"#);
    expect_error(&t, "value=\"1.5\"", "<integer", &["integer"]);
    let t = scene(r#"<shape type="sphere"><rgb name="x" value="1, 2"/></shape>"#);
    expect_error(&t, "<rgb", "<rgb", &["r, g, b"]);
    // A model parameter out of range: ParamSpec's message with the range, at the property's line.
    let t = scene(
        r#"<shape type="sphere">
        <bsdf type="roughconductor">
            <float name="alpha" value="5"/>
        </bsdf></shape>"#,
    );
    expect_error(&t, "name=\"alpha\"", "<float name=\"alpha\">", &["'alpha'", "[0.0001, 1]"]);
    let t = scene(r#"<shape type="sphere"><bsdf type="ward"><string name="ks" value="red"/></bsdf></shape>"#);
    expect_error(&t, "name=\"ks\"", "<string name=\"ks\">", &["'ks'", "<rgb>"]);
    let t = scene(
        r#"<shape type="sphere"><bsdf type="roughconductor"><string name="material" value="Pt"/></bsdf></shape>"#,
    );
    expect_error(&t, "\"Pt\"", "material", &["Au", "Cu", "Al"]);
    let t =
        scene(r#"<shape type="sphere"><bsdf type="diffuse"><string name="reflectance" value="0.5"/></bsdf></shape>"#);
    expect_error(&t, "reflectance", "<string", &["<rgb>"]);
    let t = scene(r#"<shape type="sphere"><boolean name="flip_normals" value="yes"/></shape>"#);
    expect_error(&t, "yes", "<boolean", &["true|false"]);
}

#[test]
fn missing_files_refs_and_params() {
    let t = scene(r#"<shape type="ply"><string name="filename" value="nowhere.ply"/></shape>"#);
    expect_error(&t, "nowhere", "filename", &["nowhere.ply"]);
    let t = scene(r#"<emitter type="envmap"><string name="filename" value="nowhere.exr"/></emitter>"#);
    expect_error(&t, "nowhere", "filename", &["nowhere.exr"]);
    let t = scene(r#"<bsdf type="diffuse" id="red"/><shape type="sphere"><ref id="blue"/></shape>"#);
    expect_error(&t, "\"blue\"", "<ref id=\"blue\">", &["'blue'", "red"]);
    let t = scene(r#"<shape type="sphere"><float name="radius" value="$size"/></shape>"#);
    expect_error(&t, "$size", "<float name=\"radius\">", &["$size", "-D size=", "<default"]);
    let t = scene(r#"<shape type="ply"/>"#);
    expect_error(&t, "type=\"ply\"", "<shape", &["filename"]);
    let no_sensor = "<scene version=\"3.0.0\">\n<shape type=\"sphere\"/>\n</scene>";
    let e = load(no_sensor).unwrap_err().to_string();
    assert!(e.contains(":1:") && e.contains("<sensor"), "{e}");
}

#[test]
fn spot_directional_disk_and_rotated_envmap() {
    let dir = temp_dir("lights");
    // An 8×5 map whose texels differ by column, so that a rotation about +Y shows.
    let mut img = render::Image::new(8, 5);
    for y in 0..5 {
        for x in 0..8 {
            img.set(x, y, Rgb::new(x as f32 + 1.0, y as f32, 1.0));
        }
    }
    img.save(dir.join("cols.exr")).unwrap();
    let text = scene(
        r#"
    <emitter type="envmap">
        <string name="filename" value="cols.exr"/>
        <transform name="to_world"><rotate y="1" angle="90"/></transform>
    </emitter>
    <emitter type="spot">
        <transform name="to_world"><lookat origin="0, 3, 0" target="0, 0, 0" up="0, 0, 1"/></transform>
        <rgb name="intensity" value="9, 9, 9"/>
        <float name="cutoff_angle" value="30"/>
    </emitter>
    <emitter type="directional">
        <vector name="direction" x="0" y="-2" z="0"/>
        <float name="irradiance" value="3"/>
    </emitter>
    <shape type="disk">
        <transform name="to_world"><scale value="2"/><rotate x="1" angle="-90"/></transform>
    </shape>"#,
    );
    let s = load_scene_str(&text, &dir, &[]).unwrap();
    let lights = s.scene.lights();
    let Light::EnvMap(env) = &lights[0] else { panic!() };
    let plain = render::light::EnvMap::new(&img, 1.0).unwrap();
    // world = R_y(90°) · map: the map's +Z now looks along world +X.
    for d in [Vec3::X, Vec3::Z, Vec3::new(0.3, 0.5, -0.8).normalize()] {
        let map_d = Mat4::from_rotation_y(-90f32.to_radians()).transform_vector3(d);
        assert!((env.eval(d) - plain.eval(map_d)).max_channel().abs() < 1e-4, "{d:?}");
        assert!((env.pdf(d) - plain.pdf(map_d)).abs() <= 1e-3 * plain.pdf(map_d), "{d:?}");
    }
    let Light::Spot(spot) = &lights[1] else { panic!() };
    assert!(close(spot.position, Vec3::new(0.0, 3.0, 0.0)) && close(spot.axis, -Vec3::Y));
    assert!((spot.beam_width - 22.5f32.to_radians()).abs() < 1e-6, "Mitsuba's default: ¾ of the cutoff");
    let Light::Directional(sun) = &lights[2] else { panic!() };
    assert!(close(sun.direction, -Vec3::Y) && sun.irradiance == Rgb::splat(3.0));
    let Geometry::Disk(disk) = &s.scene.shapes()[0].geometry else { panic!() };
    assert!(close(disk.normal(), Vec3::Y) && (disk.area() - 4.0 * std::f32::consts::PI).abs() < 1e-4);

    // The disk under the spot (the one light: no light-selection noise), seen from above by a
    // direct-lighting render: ρ/π · I/r² = 0.5/π · 9/9 at the centre pixel.
    let text = r#"<scene version="3.0.0">
    <integrator type="direct"/>
    <sensor type="perspective">
        <float name="fov" value="5"/>
        <transform name="to_world"><lookat origin="0, 1, 0" target="0, 0, 0" up="0, 0, 1"/></transform>
        <film type="hdrfilm"><integer name="width" value="3"/><integer name="height" value="3"/><rfilter type="gaussian"/></film>
    </sensor>
    <emitter type="spot">
        <transform name="to_world"><lookat origin="0, 3, 0" target="0, 0, 0" up="0, 0, 1"/></transform>
        <rgb name="intensity" value="9, 9, 9"/>
    </emitter>
    <shape type="disk">
        <transform name="to_world"><scale value="2"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"/>
    </shape>
</scene>"#;
    let s = load_scene_str(text, &dir, &[]).unwrap();
    assert!(matches!(s.scene.camera.filter, Filter::Gaussian(_)));
    let img = render(
        &s.scene,
        &RenderOptions { spp: 64, seed: 1, threads: 1, integrator: s.integrator, ..Default::default() },
        |_| {},
    );
    let expect = 0.5 / std::f32::consts::PI;
    // Every sample sees the same radiance (the footprint is ≤ 0.2° off the axis: no falloff,
    // and < 1e-3 inverse-square change), times its filter weight w with E[w] = 1. So the pixel
    // is expect·mean(w) and lies within 4σ_w/√64 of expect, σ_w measured from a sweep of u.
    let (mut sw, mut sw2, n) = (0.0f64, 0.0f64, 200);
    for i in 0..n {
        for j in 0..n {
            let u = glam::Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            let Filter::Gaussian(g) = &s.scene.camera.filter else { unreachable!() };
            let w = g.sample(u).1 as f64;
            sw += w;
            sw2 += w * w;
        }
    }
    let m = sw / (n * n) as f64;
    let sigma_w = (sw2 / (n * n) as f64 - m * m).max(0.0).sqrt();
    assert!((m - 1.0).abs() < 1e-3, "mean filter weight {m}");
    let c = img.get(1, 1).0[0] as f64;
    let tol = (4.0 * sigma_w / 8.0 + 2e-3) * expect as f64;
    assert!((c - expect as f64).abs() < tol, "{c} vs {expect} (σ_w {sigma_w})");
    std::fs::remove_dir_all(&dir).unwrap();
}
