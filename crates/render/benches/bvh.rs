//! BVH speed on the peer benchmark's 100k-triangle torus (shared/bench/data/torus.ply), ours
//! against the `obvhs` crate (PLOC-built binary BVH and its 8-wide compressed CWBVH).
//!
//! First a table: build times, then closest-hit Mrays/s for the same 1M rays through each
//! hierarchy — camera rays of shared/bench/scenes/mesh.xml (512×512, 4 jittered samples per
//! pixel) and random rays (origins uniform in the torus's box enlarged 10 %, directions
//! uniform on the sphere) — on 1 and 2 rayon threads. The first three rows call the same
//! scalar triangle test, one triangle at a time, on the same triangle array (reordered to
//! each leaf order), so they compare hierarchies, not triangle tests (ours has leaves of up to
//! twelve triangles, sized for the sixteen-wide test, so one at a time it tests more of them);
//! the last row is what the renderer runs, `Scene::intersect_t`: our hierarchy with a leaf's
//! triangles in one test.
//! Before timing, the hit distances of a subset are checked to agree between all rows.
//!
//! Then criterion runs for the renderer's path alone (camera, diffuse bounce and shadow
//! rays, build), for tracking regressions. Skipped when the mesh is absent.

use criterion::{Criterion, Throughput};
use glam::{Vec2, Vec3};
use obvhs::{
    bvh2::builder::build_bvh2_from_tris, cwbvh::builder::build_cwbvh_from_tris, ray::RayHit, triangle::Triangle,
    BvhBuildParams,
};
use radiometry::warp::{cosine_hemisphere, uniform_sphere};
use rayon::prelude::*;
use render::bvh::Bvh;
use render::camera::{look_at, Camera, FovAxis};
use render::ray::{spawn_ray, spawn_ray_to, Ray};
use render::sampler::Sampler;
use render::scene::{lanes_of, LightNumbers};
use render::shape::mesh::intersect_triangle;
use render::shape::{Aabb, Geometry, TriangleMesh};
use render::{Scene, SceneBuilder, Shape};
use std::cell::Cell;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Jittered samples per pixel of the camera rays: 512² × 4 ≈ 1M rays.
const CAMERA_SPP: u32 = 4;
/// Random rays traced.
const RANDOM_RAYS: usize = 1 << 20;
/// Rays per rayon task: large enough that scheduling costs nothing, small enough to balance.
const CHUNK: usize = 4096;
/// Every this many rays is checked for agreement between the hierarchies.
const CHECK_STRIDE: usize = 16;
/// Timed repetitions per case; the best is reported (the machine is shared).
const REPS: usize = 5;

fn torus_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/bench/data/torus.ply")
}

/// The camera of shared/bench/scenes/mesh.xml.
fn camera() -> Camera {
    let to_world = look_at(Vec3::new(0.0, 1.4, 5.0), Vec3::ZERO, Vec3::Y).expect("valid look-at");
    Camera::new(to_world, 40.0, FovAxis::X, 512, 512)
}

/// A triangle as the hot loop wants it: a corner and two edges.
#[derive(Clone, Copy)]
struct Tri {
    p0: Vec3,
    e1: Vec3,
    e2: Vec3,
}

impl Tri {
    #[inline]
    fn hit(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        intersect_triangle(o, d, t_max, self.p0, self.e1, self.e2).map(|h| h.0)
    }
}

/// The hierarchies under comparison, each with the triangles in its own leaf order, and
/// the renderer's scene.
struct Contenders {
    ours: (Bvh, Vec<Tri>),
    bvh2: (obvhs::bvh2::Bvh2, Vec<Tri>),
    cwbvh: (obvhs::cwbvh::CwBvh, Vec<Tri>),
    scene: Scene,
}

/// Rows of the table, in [`NAMES`] order.
const ROWS: usize = 4;

/// The closest-hit distance of `ray` through row `which` (0 ours, 1 obvhs BVH2, 2 CWBVH,
/// 3 the scene).
#[inline]
fn trace(c: &Contenders, which: usize, ray: &Ray) -> Option<f32> {
    trace_counted::<false>(c, which, ray, &Cell::new(0))
}

/// [`trace`], adding the number of triangle tests to `tests` when `COUNT`.
#[inline]
fn trace_counted<const COUNT: bool>(c: &Contenders, which: usize, ray: &Ray, tests: &Cell<u64>) -> Option<f32> {
    let (o, d) = (ray.o, ray.d);
    let hit = |t: &Tri, t_max: f32| {
        if COUNT {
            tests.set(tests.get() + 1);
        }
        t.hit(o, d, t_max)
    };
    match which {
        0 => {
            let (bvh, tris) = &c.ours;
            bvh.closest(ray, |k, t_max| hit(&tris[k], t_max)).map(|h| h.1)
        }
        3 => c.scene.intersect_t(ray).map(|h| h.1),
        _ => {
            // obvhs takes its own glam version's vectors; arrays bridge the two.
            let r = obvhs::ray::Ray::new(o.to_array().into(), d.to_array().into(), 0.0, ray.t_max);
            let mut rh = RayHit::none();
            let test = |tris: &[Tri], r: &obvhs::ray::Ray, k: usize| hit(&tris[k], r.tmax).unwrap_or(f32::INFINITY);
            let found = if which == 1 {
                let (bvh, tris) = &c.bvh2;
                bvh.ray_traverse(r, &mut rh, |r, k| test(tris, r, k))
            } else {
                let (bvh, tris) = &c.cwbvh;
                bvh.ray_traverse(r, &mut rh, |r, k| test(tris, r, k))
            };
            found.then_some(rh.t)
        }
    }
}

const NAMES: [&str; ROWS] =
    ["ours (SAH, 8-wide)", "obvhs BVH2 (PLOC)", "obvhs CWBVH (8-wide)", "ours, a leaf per test"];

fn timed<T>(f: impl FnOnce() -> T) -> (T, Duration) {
    let t = Instant::now();
    let v = f();
    (v, t.elapsed())
}

fn build(mesh: &TriangleMesh) -> Contenders {
    let tris: Vec<Tri> = (0..mesh.len())
        .map(|i| {
            let [a, b, c] = mesh.triangle(i);
            Tri { p0: a, e1: b - a, e2: c - a }
        })
        .collect();
    let reorder = |order: &[u32]| order.iter().map(|&i| tris[i as usize]).collect::<Vec<_>>();

    let (ours, t_ours) = timed(|| {
        let bounds: Vec<Aabb> = (0..mesh.len()).map(|i| mesh.triangle_bounds(i)).collect();
        Bvh::build(&bounds)
    });
    let (scene, t_scene) = timed(|| torus_scene(mesh.clone()));
    let otris: Vec<Triangle> = (0..mesh.len())
        .map(|i| {
            let [a, b, c] = mesh.triangle(i);
            Triangle { v0: a.to_array().into(), v1: b.to_array().into(), v2: c.to_array().into() }
        })
        .collect();
    // medium_build: obvhs's preset meant to match Embree's build time.
    let params = BvhBuildParams::medium_build();
    let (bvh2, t_bvh2) = timed(|| build_bvh2_from_tris(&otris, params, &mut Duration::default()));
    let (cwbvh, t_cw) = timed(|| build_cwbvh_from_tris(&otris, params, &mut Duration::default()));
    println!("build, one thread, {} triangles:", mesh.len());
    println!("  {:<26} {:>8.1} ms  {:>7} nodes", NAMES[0], t_ours.as_secs_f64() * 1e3, ours.node_count());
    println!("  {:<26} {:>8.1} ms  {:>7} nodes", NAMES[1], t_bvh2.as_secs_f64() * 1e3, bvh2.nodes.len());
    println!("  {:<26} {:>8.1} ms  {:>7} nodes", NAMES[2], t_cw.as_secs_f64() * 1e3, cwbvh.nodes.len());
    println!("  {:<26} {:>8.1} ms  (the whole scene, packs included)", NAMES[3], t_scene.as_secs_f64() * 1e3);
    let (t0, t1, t2) = (reorder(&ours.order), reorder(&bvh2.primitive_indices), reorder(&cwbvh.primitive_indices));
    Contenders { ours: (ours, t0), bvh2: (bvh2, t1), cwbvh: (cwbvh, t2), scene }
}

/// 512×512 pixels × [`CAMERA_SPP`] box-filtered jittered samples, per-pixel streams.
fn camera_rays(cam: &Camera) -> Vec<Ray> {
    let mut rays = Vec::with_capacity((cam.width * cam.height * CAMERA_SPP) as usize);
    for s in 0..CAMERA_SPP {
        for y in 0..cam.height {
            for x in 0..cam.width {
                let pixel = u64::from(y * cam.width + x);
                let u = Sampler::new(7, pixel, u64::from(s)).next_2d();
                rays.push(cam.ray(Vec2::new(x as f32, y as f32) + u, Vec2::splat(0.5)));
            }
        }
    }
    rays
}

/// Origins uniform in the box enlarged 10 % about its centre, directions uniform on the sphere.
fn random_rays(bounds: Aabb, n: usize) -> Vec<Ray> {
    let (c, h) = (bounds.center(), (bounds.max - bounds.min) * 0.5 * 1.1);
    (0..n)
        .map(|i| {
            let mut s = Sampler::new(11, i as u64, 0);
            let u = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d());
            Ray::new(c + h * (2.0 * u - Vec3::ONE), uniform_sphere(s.next_2d()))
        })
        .collect()
}

/// Checks every [`CHECK_STRIDE`]-th ray: the same hit or miss, distances within 1e-4 relative.
fn check(c: &Contenders, name: &str, rays: &[Ray]) {
    let (mut n, mut hits, mut bad) = (0, 0, 0);
    let tests = [Cell::new(0), Cell::new(0), Cell::new(0), Cell::new(0)];
    for r in rays.iter().step_by(CHECK_STRIDE) {
        let t: Vec<Option<f32>> = (0..ROWS).map(|w| trace_counted::<true>(c, w, r, &tests[w])).collect();
        n += 1;
        hits += t[0].is_some() as usize;
        let agree = |a: Option<f32>, b: Option<f32>| match (a, b) {
            (None, None) => true,
            (Some(a), Some(b)) => (a - b).abs() <= 1e-4 * a.abs().max(b.abs()),
            _ => false,
        };
        if !(agree(t[0], t[1]) && agree(t[0], t[2]) && t[3] == t[0]) {
            bad += 1;
            if bad <= 5 {
                eprintln!("  disagreement on {r:?}: {t:?}");
            }
        }
    }
    let per_ray = tests.map(|t| t.get() as f64 / n.max(1) as f64);
    println!(
        "  check {name}: {n} rays ({hits} hits), {bad} disagree; triangle tests per ray: {:.1} / {:.1} / {:.1}",
        per_ray[0], per_ray[1], per_ray[2]
    );
    assert_eq!(bad, 0, "the hierarchies disagree on {bad} of {n} {name} rays");
}

/// Best-of-[`REPS`] Mrays/s for tracing `rays` through each hierarchy on `pool`. The
/// hierarchies take turns within each repetition, so a load spike from other processes
/// cannot favour one of them.
fn mrays(pool: &rayon::ThreadPool, c: &Contenders, rays: &[Ray]) -> [f64; ROWS] {
    let mut best = [Duration::MAX; ROWS];
    for _ in 0..REPS {
        for (which, b) in best.iter_mut().enumerate() {
            let (hits, dt) = timed(|| {
                pool.install(|| {
                    rays.par_chunks(CHUNK)
                        .map(|ch| ch.iter().filter(|r| trace(c, which, black_box(r)).is_some()).count())
                        .sum::<usize>()
                })
            });
            black_box(hits);
            *b = (*b).min(dt);
        }
    }
    best.map(|t| rays.len() as f64 / t.as_secs_f64().max(1e-9) * 1e-6)
}

fn comparison(mesh: &TriangleMesh) {
    let c = build(mesh);
    let sets = [("camera", camera_rays(&camera())), ("random", random_rays(c.ours.0.bounds(), RANDOM_RAYS))];
    for (name, rays) in &sets {
        check(&c, name, rays);
    }
    let threads = [1, 2];
    let pools: Vec<_> =
        threads.iter().map(|&t| rayon::ThreadPoolBuilder::new().num_threads(t).build().expect("thread pool")).collect();
    let columns: Vec<[f64; ROWS]> =
        sets.iter().flat_map(|(_, rays)| pools.iter().map(|pool| mrays(pool, &c, rays))).collect();
    println!("closest hit, Mrays/s (best of {REPS}):");
    println!("  {:<26} {:>10} {:>10} {:>10} {:>10}", "", "camera 1t", "camera 2t", "random 1t", "random 2t");
    for (which, name) in NAMES.iter().enumerate() {
        let row: String = columns.iter().map(|col| format!(" {:>10.2}", col[which])).collect();
        println!("  {name:<26}{row}");
    }
    println!("  ({} camera rays, {} random rays)", sets[0].1.len(), sets[1].1.len());
    shadow_table(&pools, &c.scene);
    packet_table(&pools, &c.scene, &sets[1].1);
    cost_split(&c.scene);
}

/// Where one camera sample's time goes, on one thread, for a direct-lighting sample with one
/// bounce on the torus: each stage of the renderer timed over every sample of a 512² image
/// (ns per camera sample). The stages are those `Integrator::li_packet` runs, apart.
fn cost_split(torus: &Scene) {
    use render::film::SplatFilm;
    use render::light::RefPoint;
    use render::sampler::PixelKey;
    use render::simd::{Simd, LANES};
    let simd = Simd::detect();
    // The torus lit by a rectangle light above it.
    let mut b = SceneBuilder::new(camera());
    let mesh = torus.shapes()[0].clone();
    b.shape(mesh);
    let m = glam::Mat4::from_translation(Vec3::new(0.0, 3.0, 0.0))
        * glam::Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let dark: std::sync::Arc<dyn brdf::Brdf> = brdf::build("lambert", &[("albedo", "0")]).expect("lambert").into();
    let mut light = Shape::new(Geometry::Rectangle(render::shape::Rectangle::new(&m).expect("a rectangle")), dark);
    light.emission = Some(render::texture::Texture::Constant(radiometry::Rgb::splat(5.0)));
    b.shape(light);
    let scene = b.build().expect("a valid scene");
    let cam = &scene.camera;
    let n = (cam.width * cam.height) as usize;
    let mut stages: Vec<(&str, f64)> = Vec::new();
    let mut time = |name, f: &mut dyn FnMut()| {
        let best = (0..3).map(|_| timed(&mut *f).1).min().unwrap_or(Duration::MAX);
        stages.push((name, best.as_secs_f64() * 1e9 / n as f64));
    };
    let mut samplers = Vec::new();
    let mut rays = Vec::new();
    time("camera ray and sampler", &mut || {
        samplers.clear();
        rays.clear();
        for pixel in 0..n as u64 {
            let mut s = PixelKey::new(3, pixel).sampler(0);
            let pos = Vec2::new((pixel % cam.width as u64) as f32, (pixel / cam.width as u64) as f32) + s.next_2d();
            rays.push(cam.ray(pos, Vec2::splat(0.5)));
            samplers.push(s);
        }
    });
    let packets = |rays: &[Ray]| -> Vec<([Ray; LANES], u32)> { rays.chunks(LANES).map(lanes_of).collect() };
    let camera_packets = packets(&rays);
    let mut hits = Vec::new();
    time("camera rays (packets)", &mut || {
        hits.clear();
        for (p, active) in &camera_packets {
            hits.extend(scene.intersect_t_packet(p, *active, simd).into_iter().take(active.count_ones() as usize));
        }
    });
    let mut interactions = Vec::new();
    time("surface data at the hits", &mut || {
        interactions =
            rays.iter().zip(&hits).filter_map(|(r, h)| h.map(|(k, t)| (r.d, scene.interaction(r, k, t)))).collect();
    });
    let mut bounces = Vec::new();
    let mut shadows = Vec::new();
    time("BRDF sample and eval", &mut || {
        bounces.clear();
        for ((d, si), s) in interactions.iter().zip(samplers.iter_mut()) {
            let wo = si.frame.to_local(-*d);
            scene.material(si.shape).with(si, |brdf| {
                if let Some(bs) = brdf.sample(wo, s.next_1d(), s.next_2d()) {
                    black_box(brdf.eval_pdf(bs.wi, wo));
                    bounces.push(spawn_ray(si.p, si.ng, si.frame.to_world(bs.wi)));
                }
            });
        }
    });
    time("light sample and shadow ray", &mut || {
        shadows.clear();
        for ((_, si), s) in interactions.iter().zip(samplers.iter_mut()) {
            let r = RefPoint { p: si.p, n: Some(si.frame.n) };
            for ls in scene.sample_lights(&r, &LightNumbers::draw(s, &scene), true).iter().flatten() {
                if let Some((ray, _)) = scene.shadow_ray(si.p, si.ng, ls) {
                    shadows.push(ray);
                }
            }
        }
    });
    let shadow_packets = packets(&shadows);
    let none = [None; LANES];
    time("shadow rays (packets)", &mut || {
        for (p, active) in &shadow_packets {
            black_box(scene.occluded_packet(p, &none, *active, simd));
        }
    });
    time("bounce rays (one at a time)", &mut || {
        for r in &bounces {
            black_box(scene.intersect_t(r));
        }
    });
    time("film (Gaussian splats)", &mut || {
        let filter = render::filter::Filter::gaussian(0.5).expect("a filter");
        let film = SplatFilm::new(&filter, cam.width as usize, cam.height as usize);
        let mut row = film.row_splats();
        let w = cam.width as usize;
        let ones = vec![radiometry::Rgb::ONE; w];
        for y in 0..rays.len() / w {
            row.reset(y);
            let at: Vec<(usize, Vec2)> = (0..w).map(|x| (x, Vec2::new(x as f32 + 0.5, y as f32 + 0.5))).collect();
            row.splat_batch(&at, &ones, simd);
        }
        black_box(&row);
    });
    let total: f64 = stages.iter().map(|s| s.1).sum();
    println!(
        "cost of one camera sample, one thread ({} packets; {n} samples, {} hits, {} bounces, {} shadow rays):",
        simd.name(),
        interactions.len(),
        bounces.len(),
        shadows.len()
    );
    for (name, ns) in &stages {
        println!("  {name:<30} {ns:>8.1} ns  {:>5.1} %", 100.0 * ns / total);
    }
    println!("  {:<30} {total:>8.1} ns", "total");
}

/// The renderer's camera rays as it forms its packets: pixel by pixel along each row, a
/// pixel's [`CAMERA_SPP`] samples one after another.
fn camera_rays_by_pixel(cam: &Camera) -> Vec<Ray> {
    let mut rays = Vec::with_capacity((cam.width * cam.height * CAMERA_SPP) as usize);
    for y in 0..cam.height {
        for x in 0..cam.width {
            for s in 0..CAMERA_SPP {
                let u = Sampler::new(7, u64::from(y * cam.width + x), u64::from(s)).next_2d();
                rays.push(cam.ray(Vec2::new(x as f32, y as f32) + u, Vec2::splat(0.5)));
            }
        }
    }
    rays
}

/// Mrays/s of the renderer's queries on each instruction set, sixteen rays per call (one at a
/// time for `scalar`): closest hits of camera rays (in the renderer's packet order) and of
/// random rays, and shadow rays (any hit) from the camera hits towards a point light.
fn packet_table(pools: &[rayon::ThreadPool], scene: &Scene, random: &[Ray]) {
    use render::simd::{Simd, LANES};
    let camera = camera_rays_by_pixel(&scene.camera);
    let (_, _, shadow) = scene_rays(scene);
    let none = [None; LANES];
    println!("packets, Mrays/s (best of {REPS}; {LANES} rays per query):");
    println!(
        "  {:<26} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "", "camera 1t", "camera 2t", "random 1t", "random 2t", "shadow 1t", "shadow 2t"
    );
    for simd in Simd::ALL.map(|(_, s)| s).into_iter().filter(|s| s.available()) {
        let closest = |ch: &[Ray]| {
            let (p, active) = lanes_of(ch);
            scene.intersect_t_packet(black_box(&p), active, simd).iter().filter(|h| h.is_some()).count()
        };
        let any = |ch: &[Ray]| {
            let (p, active) = lanes_of(ch);
            scene.occluded_packet(black_box(&p), &none, active, simd).count_ones() as usize
        };
        let mut row = String::new();
        for (rays, q) in
            [(&camera[..], &closest as &(dyn Fn(&[Ray]) -> usize + Sync)), (random, &closest), (&shadow, &any)]
        {
            for pool in pools {
                row += &format!(" {:>10.2}", packet_rate(pool, rays, q));
            }
        }
        println!("  {:<26}{row}", simd.name());
    }
}

/// Best-of-[`REPS`] Mrays/s of `query`, called on sixteen rays at a time, over `rays` on `pool`.
fn packet_rate(pool: &rayon::ThreadPool, rays: &[Ray], query: &(dyn Fn(&[Ray]) -> usize + Sync)) -> f64 {
    use render::simd::LANES;
    chunk_rate(pool, rays, &|ch| ch.chunks(LANES).map(query).sum())
}

/// Best-of-[`REPS`] Mrays/s of `query`, called ray by ray, over `rays` on `pool`.
fn rate(pool: &rayon::ThreadPool, rays: &[Ray], query: &(dyn Fn(&Ray) -> bool + Sync)) -> f64 {
    chunk_rate(pool, rays, &|ch| ch.iter().filter(|r| query(black_box(r))).count())
}

/// Best-of-[`REPS`] Mrays/s of `per_chunk`, which traces one rayon task's [`CHUNK`] rays.
fn chunk_rate(pool: &rayon::ThreadPool, rays: &[Ray], per_chunk: &(dyn Fn(&[Ray]) -> usize + Sync)) -> f64 {
    let best = (0..REPS)
        .map(|_| timed(|| pool.install(|| rays.par_chunks(CHUNK).map(per_chunk).sum::<usize>())).1)
        .min()
        .unwrap_or(Duration::MAX);
    rays.len() as f64 / best.as_secs_f64().max(1e-9) * 1e-6
}

/// Shadow rays from the camera rays' hits towards a point light, as the renderer traces them
/// (`Scene::occluded`, an any-hit query), against a closest-hit query of the same rays.
fn shadow_table(pools: &[rayon::ThreadPool], scene: &Scene) {
    let (_, _, shadow) = scene_rays(scene);
    let any: &(dyn Fn(&Ray) -> bool + Sync) = &|r| scene.occluded(r);
    let closest: &(dyn Fn(&Ray) -> bool + Sync) = &|r| scene.intersect_t(r).is_some();
    let blocked = shadow.iter().filter(|r| scene.occluded(r)).count();
    assert_eq!(blocked, shadow.iter().filter(|r| scene.intersect_t(r).is_some()).count(), "the two queries agree");
    println!("shadow rays, Mrays/s (best of {REPS}; {} rays, {blocked} blocked):", shadow.len());
    println!("  {:<26} {:>10} {:>10}", "", "1t", "2t");
    for (name, q) in [("any hit (Scene::occluded)", any), ("closest hit (intersect_t)", closest)] {
        let row: String = pools.iter().map(|p| format!(" {:>10.2}", rate(p, &shadow, q))).collect();
        println!("  {name:<26}{row}");
    }
}

fn torus_scene(mesh: TriangleMesh) -> Scene {
    let mut b = SceneBuilder::new(camera());
    let brdf: std::sync::Arc<dyn brdf::Brdf> = brdf::build("lambert", &[]).expect("lambert").into();
    b.shape(Shape::new(Geometry::Mesh(mesh), brdf));
    b.build().expect("a valid scene")
}

/// One ray per pixel centre, a cosine-weighted bounce from each hit, and a shadow ray from
/// each hit towards a point light above the torus.
fn scene_rays(scene: &Scene) -> (Vec<Ray>, Vec<Ray>, Vec<Ray>) {
    let cam = &scene.camera;
    let primary: Vec<Ray> = (0..cam.height)
        .flat_map(|y| (0..cam.width).map(move |x| cam.ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), Vec2::splat(0.5))))
        .collect();
    let mut s = Sampler::new(1, 0, 0);
    let hits: Vec<_> = primary.iter().filter_map(|r| scene.intersect(r)).collect();
    let bounce =
        hits.iter().map(|si| spawn_ray(si.p, si.ng, si.frame.to_world(cosine_hemisphere(s.next_2d())))).collect();
    let light = Vec3::new(2.0, 4.0, 3.0);
    let shadow = hits.iter().map(|si| spawn_ray_to(si.p, si.ng, light).0).collect();
    (primary, bounce, shadow)
}

fn criterion_runs(c: &mut Criterion, scene: &Scene, mesh: &TriangleMesh) {
    let (primary, bounce, shadow) = scene_rays(scene);
    let mut g = c.benchmark_group("bvh_torus");
    g.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    g.throughput(Throughput::Elements(primary.len() as u64));
    g.bench_function("primary_rays", |b| {
        b.iter(|| primary.iter().filter(|r| scene.intersect_t(black_box(r)).is_some()).count())
    });
    g.throughput(Throughput::Elements(bounce.len() as u64));
    g.bench_function("bounce_rays", |b| {
        b.iter(|| bounce.iter().filter(|r| scene.intersect_t(black_box(r)).is_some()).count())
    });
    g.throughput(Throughput::Elements(shadow.len() as u64));
    g.bench_function("shadow_rays", |b| b.iter(|| shadow.iter().filter(|r| scene.occluded(black_box(r))).count()));
    g.throughput(Throughput::Elements(mesh.len() as u64));
    let bounds: Vec<_> = (0..mesh.len()).map(|i| mesh.triangle_bounds(i)).collect();
    g.bench_function("build", |b| b.iter(|| Bvh::build(black_box(&bounds)).node_count()));
    g.finish();
}

fn main() {
    let mesh = match render::io::load_mesh(torus_path()) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("BVH benchmark skipped: {e}");
            return;
        }
    };
    let mut crit = Criterion::default().configure_from_args();
    comparison(&mesh);
    criterion_runs(&mut crit, &torus_scene(mesh.clone()), &mesh);
    crit.final_summary();
}
