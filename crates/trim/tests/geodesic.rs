//! Geodesics against closed forms: developable patches (cylinder, cone) unrolled into the
//! plane, where the shortest path is a straight segment; the sphere's great circle.

#![allow(clippy::unwrap_used)]

use flatcut_mesh::{FaceId, TriMesh, bvh::Bvh, shapes, vec3};
use flatcut_trim::{GeodesicOptions, GeodesicSolver, SurfacePoint};

/// xorshift64*: deterministic points without a dependency.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn point(&mut self, mesh: &TriMesh) -> SurfacePoint {
        let f = ((self.next() * mesh.faces.len() as f64) as usize).min(mesh.faces.len() - 1);
        let (a, b) = (self.next(), self.next());
        let (a, b) = if a + b > 1.0 {
            (1.0 - a, 1.0 - b)
        } else {
            (a, b)
        };
        SurfacePoint {
            face: FaceId(f as u32),
            barycentric: [1.0 - a - b, a, b],
        }
        .snapped()
    }
}

fn developed(dev: &[[f64; 2]], mesh: &TriMesh, p: SurfacePoint) -> [f64; 2] {
    let f = mesh.faces[p.face.idx()];
    let mut q = [0.0; 2];
    for k in 0..3 {
        q[0] += p.barycentric[k] * dev[f[k] as usize][0];
        q[1] += p.barycentric[k] * dev[f[k] as usize][1];
    }
    q
}

/// Checks that consecutive path points share a face and returns the largest relative error
/// of the length against the developed straight segment over `pairs` random pairs.
fn worst_developable_error(mesh: &TriMesh, dev: &[[f64; 2]], pairs: usize, seed: u64) -> f64 {
    // The development must be an isometry of every face (independent check of `dev`).
    for f in &mesh.faces {
        for k in 0..3 {
            let (a, b) = (f[k] as usize, f[(k + 1) % 3] as usize);
            let d3 = vec3::dist(mesh.positions[a], mesh.positions[b]);
            let d2 = (dev[a][0] - dev[b][0]).hypot(dev[a][1] - dev[b][1]);
            assert!((d3 - d2).abs() < 1e-9 * d3, "development is not isometric");
        }
    }
    let solver = GeodesicSolver::new(mesh, &GeodesicOptions::default()).unwrap();
    let mut rng = Rng(seed);
    let mut worst: f64 = 0.0;
    for _ in 0..pairs {
        let (a, b) = (rng.point(mesh), rng.point(mesh));
        let g = solver.path(a, b).expect("connected");
        let (pa, pb) = (developed(dev, mesh, a), developed(dev, mesh, b));
        let exact = (pa[0] - pb[0]).hypot(pa[1] - pb[1]);
        for w in g.points.windows(2) {
            let shared = mesh.faces[w[0].face.idx()]
                .iter()
                .filter(|v| mesh.faces[w[1].face.idx()].contains(v))
                .count();
            assert!(
                shared >= 2 || w[0].face == w[1].face,
                "segment leaves the surface"
            );
        }
        assert!(g.length <= g.edge_path_length + 1e-9);
        if exact > 1e-9 {
            worst = worst.max((g.length - exact).abs() / exact);
        }
    }
    worst
}

#[test]
fn cylinder_patch_matches_its_development() {
    let (r, angle, h, na, nu) = (40.0, 4.0, 120.0, 30, 25);
    let mesh = shapes::cylinder_patch(r, angle, h, na, nu);
    let step = angle / (na - 1) as f64;
    let chord = 2.0 * r * (step / 2.0).sin();
    let dev: Vec<[f64; 2]> = (0..nu)
        .flat_map(|j| (0..na).map(move |i| [i as f64 * chord, j as f64 * h / (nu - 1) as f64]))
        .collect();
    let worst = worst_developable_error(&mesh, &dev, 40, 7);
    eprintln!("worst relative error {worst:e}");
    assert!(worst < 1e-6, "worst relative length error {worst:e}");
}

#[test]
fn cone_patch_matches_its_development() {
    let (r, h, angle, na, nu) = (60.0, 90.0, 3.0, 24, 16);
    let mesh = shapes::cone_patch(r, h, angle, na, nu);
    let apex = *mesh.positions.last().unwrap();
    // Developed: distance from the apex and the accumulated angle between rulings (from the
    // 3D ruling vectors, so the development does not trust the generator's formula).
    let ruling = |i: usize| vec3::sub(mesh.positions[i], apex);
    let mut phi = vec![0.0];
    for i in 1..na {
        phi.push(phi[i - 1] + vec3::angle(ruling(i - 1), ruling(i)));
    }
    assert!(
        phi[na - 1] < std::f64::consts::PI,
        "development must be convex"
    );
    let mut dev = Vec::new();
    for j in 0..nu {
        for (i, &ph) in phi.iter().enumerate() {
            let d = vec3::norm(ruling(j * na + i));
            dev.push([d * ph.cos(), d * ph.sin()]);
        }
    }
    dev.push([0.0, 0.0]);
    let worst = worst_developable_error(&mesh, &dev, 40, 11);
    eprintln!("worst relative error {worst:e}");
    assert!(worst < 1e-6, "worst relative length error {worst:e}");
}

/// Relative error of the geodesic against the great-circle arc between the same two
/// directions, averaged over a few pairs, on the icosphere of `subdivisions`.
fn sphere_error(subdivisions: usize) -> f64 {
    let r = 100.0;
    let mesh = shapes::icosphere(r, subdivisions);
    let bvh = Bvh::build(&mesh);
    let solver = GeodesicSolver::new(&mesh, &GeodesicOptions::default()).unwrap();
    let dirs = [
        ([0.2, 0.9, 0.1], [0.7, -0.4, 0.5]),
        ([-0.6, 0.3, 0.7], [0.5, 0.5, -0.6]),
        ([0.1, -0.8, 0.3], [-0.9, 0.2, -0.1]),
    ];
    let mut sum = 0.0;
    for (a, b) in dirs {
        let (a, b) = (vec3::normalize(a), vec3::normalize(b));
        let sa =
            flatcut_trim::surface_point(&bvh, vec3::scale(a, r), "a", &Default::default()).unwrap();
        let sb =
            flatcut_trim::surface_point(&bvh, vec3::scale(b, r), "b", &Default::default()).unwrap();
        let g = solver.path(sa, sb).unwrap();
        let exact = r * vec3::angle(a, b);
        sum += (g.length - exact).abs() / exact;
    }
    sum / dirs.len() as f64
}

#[test]
fn sphere_geodesic_converges_to_the_great_circle() {
    let e: Vec<f64> = (3..=5).map(sphere_error).collect();
    eprintln!("sphere mean relative error at 3/4/5 subdivisions: {e:?}");
    // 20 480 faces at 5 subdivisions.
    assert!(e[2] < 1e-3, "errors {e:?}");
    assert!(
        e[0] > e[1] && e[1] > e[2],
        "errors must fall with resolution: {e:?}"
    );
}

#[test]
fn points_in_one_face_are_joined_directly() {
    let mesh = shapes::planar_disk(50.0, 4);
    let solver = GeodesicSolver::new(&mesh, &GeodesicOptions::default()).unwrap();
    let a = SurfacePoint {
        face: FaceId(5),
        barycentric: [0.2, 0.3, 0.5],
    };
    let b = SurfacePoint {
        face: FaceId(5),
        barycentric: [0.6, 0.3, 0.1],
    };
    let g = solver.path(a, b).unwrap();
    assert_eq!(g.points.len(), 2);
    let d = vec3::dist(a.position(&mesh), b.position(&mesh));
    assert!((g.length - d).abs() < 1e-12);
}
