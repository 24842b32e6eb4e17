//! The hierarchy inside a scene against brute force: every ray's closest hit (primitive and
//! distance) and its occlusion must equal those of testing every primitive.

use crate::camera::{look_at, Camera, FovAxis};
use crate::ray::{spawn_ray, Ray};
use crate::sampler::Sampler;
use crate::scene::{lanes_of, PacketHits};
use crate::shape::{Disk, Geometry, Rectangle, Sphere, TriangleMesh};
use crate::simd::{Simd, LANES};
use crate::{Scene, SceneBuilder, Shape};
use glam::{EulerRot, Mat4, Quat, Vec2, Vec3};
use radiometry::warp::uniform_sphere;

fn builder() -> SceneBuilder {
    SceneBuilder::new(Camera::new(look_at(Vec3::Z * 10.0, Vec3::ZERO, Vec3::Y).unwrap(), 40.0, FovAxis::X, 8, 8))
}

fn add(b: &mut SceneBuilder, g: Geometry) {
    b.shape(Shape::new(g, brdf::build("lambert", &[]).unwrap()));
}

/// Uniform numbers in [lo, hi) from a fixed stream.
struct Rnd(Sampler);

impl Rnd {
    fn new(seed: u64) -> Self {
        Rnd(Sampler::new(seed, 0, 0))
    }
    fn f(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.0.next_1d()
    }
    fn v(&mut self, h: f32) -> Vec3 {
        Vec3::new(self.f(-h, h), self.f(-h, h), self.f(-h, h))
    }
    fn dir(&mut self) -> Vec3 {
        uniform_sphere(Vec2::new(self.0.next_1d(), self.0.next_1d()))
    }
}

/// `n` triangles with corners within `size` of random centres in [-5, 5]³.
fn soup(r: &mut Rnd, n: u32, size: f32) -> TriangleMesh {
    let mut pos = Vec::new();
    for _ in 0..n {
        let c = r.v(5.0);
        pos.extend([c + r.v(size), c + r.v(size), c + r.v(size)]);
    }
    TriangleMesh::new(pos, None, (0..n).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect()).unwrap()
}

/// A `n`×`n` grid of unit squares in the plane z = 0: axis-aligned triangles, flat boxes.
fn grid(n: u32) -> TriangleMesh {
    let pos = (0..=n)
        .flat_map(|y| (0..=n).map(move |x| Vec3::new(x as f32 - 0.5 * n as f32, y as f32 - 0.5 * n as f32, 0.0)));
    let at = |x: u32, y: u32| y * (n + 1) + x;
    let idx = (0..n).flat_map(|y| {
        (0..n)
            .flat_map(move |x| [[at(x, y), at(x + 1, y), at(x + 1, y + 1)], [at(x, y), at(x + 1, y + 1), at(x, y + 1)]])
    });
    TriangleMesh::new(pos.collect(), None, idx.collect()).unwrap()
}

/// A random placement, scaled by up to 1 in x and y.
fn transform(r: &mut Rnd) -> Mat4 {
    let scale = Vec3::new(r.f(0.2, 1.0), r.f(0.2, 1.0), 1.0);
    let rot = Quat::from_euler(EulerRot::XYZ, r.f(0.0, 6.0), r.f(0.0, 6.0), r.f(0.0, 6.0));
    Mat4::from_scale_rotation_translation(scale, rot, r.v(5.0))
}

/// Compares the BVH with brute force on `ray`; returns whether it hit.
fn agree(scene: &Scene, ray: &Ray) -> bool {
    let fast = scene.intersect_t(ray);
    let slow = scene.intersect_t_linear(ray);
    match (fast, slow) {
        // Equal distances, so a different primitive only at an exact tie (a shared edge).
        (Some((_, tf)), Some((_, ts))) => assert_eq!(tf, ts, "{ray:?}: {fast:?} vs {slow:?}"),
        (None, None) => {}
        _ => panic!("{ray:?}: BVH {fast:?} vs brute force {slow:?}"),
    }
    assert_eq!(scene.occluded(ray), slow.is_some(), "{ray:?}");
    slow.is_some()
}

/// Sixteen rays at a time, on every instruction set this CPU runs, against one at a time: the
/// same distances bit for bit (the primitive may differ only at an exact tie) and the same
/// occlusion, with some lanes inactive and some skipping one shape's analytic primitives.
fn packets_agree(scene: &Scene, rays: &[Ray]) {
    let shapes = scene.shapes().len() as u32;
    for (c, chunk) in rays.chunks(LANES).enumerate() {
        let (lanes, full) = lanes_of(chunk);
        let active = if c % 3 == 0 { full & 0xb5a7 } else { full };
        let skip: [Option<u32>; LANES] = std::array::from_fn(|i| (i % 3 == 0).then(|| (c + i) as u32 % shapes.max(1)));
        for simd in Simd::ALL.map(|(_, s)| s).into_iter().filter(|s| s.available()) {
            // The packet kernels themselves, and the queries that choose them for coherent rays.
            let hits = scene.intersect_t_packet_as(&lanes, active, simd);
            let blocked = scene.occluded_packet_as(&lanes, &skip, active, simd);
            let t = |h: &PacketHits| h.map(|h| h.map(|(_, t)| t.to_bits()));
            assert_eq!(t(&hits), t(&scene.intersect_t_packet(&lanes, active, simd)));
            assert_eq!(blocked, scene.occluded_packet(&lanes, &skip, active, simd));
            for (i, ray) in lanes.iter().enumerate() {
                let on = active >> i & 1 != 0;
                let single = if on { scene.intersect_t(ray) } else { None };
                match (hits[i], single) {
                    (Some((kp, tp)), Some((ks, ts))) => {
                        assert_eq!(tp.to_bits(), ts.to_bits(), "{simd:?} lane {i} {ray:?}");
                        if kp != ks {
                            assert_eq!(scene.interaction(ray, kp, tp).t, ts, "{simd:?}: a tie");
                        }
                    }
                    (p, s) => assert_eq!(p, s, "{simd:?} lane {i} {ray:?}"),
                }
                let occluded = on && scene.occluded_but(ray, skip[i]);
                assert_eq!(blocked >> i & 1 != 0, occluded, "{simd:?} lane {i} {ray:?} skip {:?}", skip[i]);
            }
        }
    }
}

/// Random rays, axis-parallel rays, and rays leaving the surfaces those hit (offset as the
/// renderer spawns them, and from the unrounded hit point itself); then the same rays as
/// packets.
fn check(scene: &Scene, r: &mut Rnd, rays: usize) -> usize {
    let mut all = Vec::new();
    let hits = check_rays(scene, r, rays, &mut all);
    packets_agree(scene, &all);
    hits
}

fn check_rays(scene: &Scene, r: &mut Rnd, rays: usize, all: &mut Vec<Ray>) -> usize {
    let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
    let mut hits = 0;
    for i in 0..rays {
        let mut ray = Ray::new(r.v(6.0), r.dir());
        match i % 4 {
            0 => ray.d = axes[i / 4 % 6],
            // One zero component, the others random.
            1 => ray.d[i / 4 % 3] = if i % 8 == 1 { 0.0 } else { -0.0 },
            2 => ray.t_max = r.f(0.0, 8.0),
            _ => {}
        }
        all.push(ray);
        if !agree(scene, &ray) {
            continue;
        }
        hits += 1;
        let si = scene.intersect(&ray).expect("a hit");
        let next = [spawn_ray(si.p, si.ng, r.dir()), Ray::new(ray.at(si.t), r.dir())];
        for ray in next {
            agree(scene, &ray);
            all.push(ray);
        }
    }
    hits
}

#[test]
fn triangle_soups_match_brute_force() {
    let mut r = Rnd::new(1);
    // Small triangles, then large overlapping ones (deep overlap, many candidates per ray).
    for (n, size, rays, min_hits) in [(3000, 0.4, 6000, 1000), (400, 3.0, 3000, 1500)] {
        let mut b = builder();
        add(&mut b, Geometry::Mesh(soup(&mut r, n, size)));
        let hits = check(&b.build().unwrap(), &mut r, rays);
        assert!(hits > min_hits, "the test must exercise hits: {hits}");
    }
}

#[test]
fn a_soup_large_enough_for_the_parallel_build_matches_brute_force() {
    let mut r = Rnd::new(4);
    let mut b = builder();
    // More than twice the size below which subtrees are built sequentially.
    add(&mut b, Geometry::Mesh(soup(&mut r, 80_000, 0.15)));
    let hits = check(&b.build().unwrap(), &mut r, 2000);
    assert!(hits > 300, "the test must exercise hits: {hits}");
}

#[test]
fn flat_grids_and_mixed_shapes_match_brute_force() {
    let mut r = Rnd::new(2);
    let mut b = builder();
    add(&mut b, Geometry::Mesh(grid(12)));
    let hits = check(&b.build().unwrap(), &mut r, 3000);
    assert!(hits > 300, "{hits}");
    // Triangles mixed with spheres, rectangles and disks, so that leaves mix them.
    let mut b = builder();
    add(&mut b, Geometry::Mesh(soup(&mut r, 500, 0.5)));
    add(&mut b, Geometry::Mesh(grid(4)));
    for _ in 0..30 {
        add(&mut b, Geometry::Sphere(Sphere::new(r.v(5.0), r.f(0.1, 0.8))));
        let m = transform(&mut r);
        add(&mut b, Geometry::Rectangle(Rectangle::new(&m).unwrap()));
        let m = transform(&mut r);
        add(&mut b, Geometry::Disk(Disk::new(&m).unwrap()));
    }
    let scene = b.build().unwrap();
    let hits = check(&scene, &mut r, 6000);
    assert!(hits > 1000, "{hits}");
}

#[test]
fn a_few_analytic_shapes_tested_without_the_bvh_match_brute_force() {
    // At most eight non-triangle primitives: spheres four at a time (one pack full, one not,
    // overlapping ones included), a rectangle and a disk one by one.
    let mut r = Rnd::new(5);
    let mut b = builder();
    for i in 0..6 {
        add(&mut b, Geometry::Sphere(Sphere::new(r.v(3.0), r.f(0.5, 2.5 - 0.2 * i as f32))));
    }
    add(&mut b, Geometry::Rectangle(Rectangle::new(&transform(&mut r)).unwrap()));
    add(&mut b, Geometry::Disk(Disk::new(&transform(&mut r)).unwrap()));
    let scene = b.build().unwrap();
    let hits = check(&scene, &mut r, 4000);
    assert!(hits > 300, "the test must exercise hits: {hits}");
}

#[test]
fn a_few_triangles_beside_analytic_shapes_tested_without_the_bvh_match_brute_force() {
    // Up to sixty-four triangles (large overlapping ones included, in packs whose boxes
    // overlap) with spheres, a rectangle and a disk.
    let mut r = Rnd::new(6);
    let mut b = builder();
    add(&mut b, Geometry::Mesh(soup(&mut r, 40, 2.0)));
    add(&mut b, Geometry::Mesh(grid(2)));
    for _ in 0..3 {
        add(&mut b, Geometry::Sphere(Sphere::new(r.v(3.0), r.f(0.3, 1.5))));
    }
    add(&mut b, Geometry::Rectangle(Rectangle::new(&transform(&mut r)).unwrap()));
    add(&mut b, Geometry::Disk(Disk::new(&transform(&mut r)).unwrap()));
    let scene = b.build().unwrap();
    assert!(scene.without_bvh(), "{} primitives", scene.primitive_count());
    let hits = check(&scene, &mut r, 4000);
    assert!(hits > 300, "the test must exercise hits: {hits}");
}

#[test]
fn empty_and_single_primitive_scenes() {
    let mut r = Rnd::new(3);
    assert_eq!(check(&builder().build().unwrap(), &mut r, 100), 0);
    let mut b = builder();
    add(&mut b, Geometry::Mesh(TriangleMesh::new(vec![-Vec3::X, Vec3::X, Vec3::Y], None, vec![[0, 1, 2]]).unwrap()));
    let scene = b.build().unwrap();
    check(&scene, &mut r, 200);
    assert_eq!(scene.intersect_t(&Ray::new(Vec3::new(0.0, 0.5, 3.0), -Vec3::Z)), Some((0, 3.0)));
    assert!(scene.occluded(&Ray::new(Vec3::new(0.0, 0.5, -3.0), Vec3::Z)));
    assert!(!scene.occluded(&Ray { t_max: 2.9, ..Ray::new(Vec3::new(0.0, 0.5, -3.0), Vec3::Z) }));
    let mut b = builder();
    add(&mut b, Geometry::Sphere(Sphere::new(Vec3::ZERO, 20.0)));
    let scene = b.build().unwrap();
    // Origins lie within 6√3 < 10.4 of the centre: every ray reaches the sphere, except the
    // quarter whose t_max < 8 stops short of it.
    assert_eq!(check(&scene, &mut r, 200), 150);
}
