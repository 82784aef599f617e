//! Test surfaces: height-field grids with one diagonal per quad (the patches).
#![allow(dead_code, clippy::unwrap_used)]

use flatcut_flattenable::least_norm::{Layout, Metric};
use flatcut_mesh::{Topology, TriMesh, VertexId};

/// A piece's least-norm layout at its input: θ, A, unit weights and A Aᵀ (isotropic metric)
/// with its mean diagonal — where the step tests, the kernel benchmarks and `measure --
/// speed` start from.
pub struct AtInput {
    pub layout: Layout,
    pub theta: Vec<f64>,
    pub grad: Vec<[f64; 3]>,
    pub scale: Vec<f64>,
    pub normal: Vec<f64>,
    pub mean_diagonal: f64,
}

impl AtInput {
    pub fn new(mesh: &TriMesh) -> Self {
        let topo = Topology::build(mesh).unwrap();
        let layout = Layout::build(&topo, &mesh.faces).unwrap();
        let mut theta = vec![0.0; layout.n()];
        let mut grad = vec![[0.0; 3]; layout.entries()];
        layout.evaluate(&mesh.positions, &mut theta, &mut grad);
        let scale = vec![1.0; layout.n()];
        let mut normal = vec![0.0; layout.normal_nnz()];
        layout.normal_matrix(&grad, &Metric::isotropic(&scale), &mut normal);
        let mean_diagonal = layout.mean_diagonal(&normal);
        Self {
            layout,
            theta,
            grad,
            scale,
            normal,
            mean_diagonal,
        }
    }

    /// The isotropic metric of unit weights A Aᵀ was built with.
    pub fn metric(&self) -> Metric<'_> {
        Metric::isotropic(&self.scale)
    }

    /// The area-weighted unit normals of `mesh`'s interior vertices, in the layout's order:
    /// with [`AtInput::tangential_metric`], the metric of a robust run's first step.
    pub fn interior_normals(&self, mesh: &TriMesh) -> Vec<[f64; 3]> {
        let weighted =
            flatcut_mesh::geometry::area_weighted_vertex_normals(&mesh.positions, &mesh.faces);
        self.layout
            .interior
            .iter()
            .map(|&p| flatcut_mesh::vec3::normalize(weighted[p as usize]))
            .collect()
    }

    /// Unit weights and the default tangential penalty with `normals`: robust mode's metric.
    pub fn tangential_metric<'a>(&'a self, normals: &'a [[f64; 3]]) -> Metric<'a> {
        let penalty = flatcut_flattenable::ProcessOptions::default().tangential_penalty;
        Metric {
            scale: &self.scale,
            normals: Some(normals),
            tangential: 1.0 / (penalty * penalty),
        }
    }

    /// What a step of `process(mesh, opts)` costs against one Cholesky of this A Aᵀ (at μ =
    /// 1e-3 × its mean diagonal): four things timed in turn, `reps` times — our numeric
    /// factorisation, faer's, the piece's set-up alone (`max_iterations` 0) and the whole
    /// run — and the minimum of each kept, so that a shared machine's slow spells fall on
    /// all four alike (timed apart, one Cholesky's best varied 1.2–2.0 ms between
    /// invocations on one machine). Seconds.
    pub fn step_cost(
        &self,
        mesh: &TriMesh,
        opts: &flatcut_flattenable::ProcessOptions,
        reps: usize,
    ) -> StepCost {
        let set_up = flatcut_flattenable::ProcessOptions {
            max_iterations: Some(0),
            ..opts.clone()
        };
        let shift = 1e-3 * self.mean_diagonal;
        let mut cost = StepCost {
            cholesky: f64::INFINITY,
            faer_cholesky: f64::INFINITY,
            set_up: f64::INFINITY,
            run: f64::INFINITY,
        };
        let mut buffers = self.layout.new_factor().unwrap();
        let min_of = |best: &mut f64, f: &mut dyn FnMut()| {
            let t = std::time::Instant::now();
            f();
            *best = best.min(t.elapsed().as_secs_f64());
        };
        for _ in 0..reps {
            min_of(&mut cost.cholesky, &mut || {
                self.layout
                    .refactor(&mut buffers, &self.normal, shift, None)
                    .unwrap();
            });
            min_of(&mut cost.faer_cholesky, &mut || {
                self.layout
                    .refactor_with_faer(&mut buffers, &self.normal, shift, None)
                    .unwrap();
            });
            min_of(&mut cost.set_up, &mut || {
                std::hint::black_box(flatcut_flattenable::process(mesh, &set_up).is_ok());
            });
            min_of(&mut cost.run, &mut || {
                std::hint::black_box(flatcut_flattenable::process(mesh, opts).is_ok());
            });
        }
        cost
    }
}

/// Minima of [`AtInput::step_cost`] (seconds).
pub struct StepCost {
    pub cholesky: f64,
    pub faer_cholesky: f64,
    pub set_up: f64,
    pub run: f64,
}

impl StepCost {
    /// A factorisation's share of the run after its set-up, for a run of `factorizations`.
    pub fn per_factorization(&self, factorizations: usize) -> f64 {
        (self.run - self.set_up) / factorizations.max(1) as f64
    }
}

/// N×N vertices on [−half, half]², z = height(x, y), faces counter-clockwise from +z.
///
/// Not `flatcut_mesh::shapes::grid_patch` on purpose: that one alternates the diagonals
/// around the centre, while the and the prototype's patches have one diagonal per
/// quad all the same way, and the measured tables in docs/algorithms/flattenable.md (the
/// saddle's result depends on round-off) are reproduced on exactly these grids.
pub fn grid(n: usize, half: f64, height: impl Fn(f64, f64) -> f64) -> TriMesh {
    let mut positions = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            let x = -half + 2.0 * half * i as f64 / (n - 1) as f64;
            let y = -half + 2.0 * half * j as f64 / (n - 1) as f64;
            positions.push([x, y, height(x, y)]);
        }
    }
    let mut faces = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (j * n + i) as u32;
            let b = a + 1;
            let c = a + n as u32;
            let d = c + 1;
            faces.push([a, b, d]);
            faces.push([a, d, c]);
        }
    }
    TriMesh::new(positions, faces).unwrap()
}

/// The 60° sphere cap of the issue: unit sphere over x, y ∈ [−0.5, 0.5].
pub fn sphere_cap(n: usize) -> TriMesh {
    grid(n, 0.5, |x, y| (1.0 - x * x - y * y).sqrt())
}

/// The criterion bench's cap (benches/process.rs), the one the speed tables and the large-cap
/// tests use: `grid_patch`'s n×n grid with alternating diagonals on the unit sphere.
pub fn bench_cap(n: usize) -> TriMesh {
    flatcut_mesh::shapes::grid_patch(n, n, 1.0, |x, y| (1.0 - x * x - y * y).sqrt())
}

/// The saddle z = 0.3(x² − y²) on [−1, 1]².
pub fn saddle(n: usize) -> TriMesh {
    grid(n, 1.0, |x, y| 0.3 * (x * x - y * y))
}

/// A planar grid.
pub fn planar(n: usize) -> TriMesh {
    grid(n, 1.0, |_, _| 0.0)
}

/// A cylinder patch of radius r: x ∈ [−1, 1] mapped onto the cylinder around the y axis.
pub fn cylinder(n: usize, r: f64) -> TriMesh {
    let mut m = grid(n, 1.0, |_, _| 0.0);
    for p in &mut m.positions {
        let a = p[0] / r;
        *p = [r * a.sin(), p[1], r * a.cos()];
    }
    m
}

/// Number of boundary vertices changed bit-wise.
pub fn boundary_changed(a: &TriMesh, b: &TriMesh) -> usize {
    let topo = flatcut_mesh::Topology::build(a).unwrap();
    (0..a.vertex_count())
        .filter(|&v| topo.is_boundary_vertex(flatcut_mesh::VertexId(v as u32)))
        .filter(|&v| a.positions[v] != b.positions[v])
        .count()
}

/// A piece of a body: the faces whose centroid passes `keep`, their largest connected part.
pub fn cut(mesh: &TriMesh, keep: impl Fn([f64; 3]) -> bool) -> TriMesh {
    let faces: Vec<u32> = (0..mesh.face_count() as u32)
        .filter(|&f| {
            let c = mesh.faces[f as usize].iter().fold([0.0; 3], |mut c, &v| {
                for (ck, pk) in c.iter_mut().zip(mesh.positions[v as usize]) {
                    *ck += pk / 3.0;
                }
                c
            });
            keep(c)
        })
        .collect();
    largest_part(mesh, &faces)
}

/// The largest face-connected part of the sub-mesh made of `faces`.
pub fn largest_part(mesh: &TriMesh, faces: &[u32]) -> TriMesh {
    let (sub, _) = flatcut_mesh::submesh(mesh, faces);
    let topo = flatcut_mesh::Topology::build(&sub).unwrap();
    let comp = topo.face_components();
    let mut count = vec![0usize; topo.component_count()];
    for &c in comp {
        count[c as usize] += 1;
    }
    let big = (0..count.len()).max_by_key(|&c| count[c]).unwrap();
    let keep_faces: Vec<u32> = (0..sub.face_count() as u32)
        .filter(|&f| comp[f as usize] as usize == big)
        .collect();
    flatcut_mesh::submesh(&sub, &keep_faces).0
}

/// The longest side of `mesh`'s bounding box (0 without faces): a body's height, or its arm
/// span in a T-pose.
pub fn largest_side(mesh: &TriMesh) -> f64 {
    mesh.bounding_box().map_or(0.0, |(lo, hi)| {
        (0..3).map(|c| hi[c] - lo[c]).fold(0.0, f64::max)
    })
}

/// `k` patch centres spread over `mesh` by farthest-point sampling (Euclidean, from vertex
/// 0; deterministic).
pub fn spread_vertices(mesh: &TriMesh, k: usize) -> Vec<u32> {
    let n = mesh.vertex_count();
    let mut near = vec![f64::INFINITY; n];
    let mut out = Vec::with_capacity(k);
    let mut next = 0usize;
    for _ in 0..k.min(n) {
        out.push(next as u32);
        let c = mesh.positions[next];
        for (v, d) in near.iter_mut().enumerate() {
            *d = d.min(flatcut_mesh::vec3::dist(c, mesh.positions[v]));
        }
        next = (0..n)
            .max_by(|&a, &b| near[a].total_cmp(&near[b]))
            .unwrap_or(0);
    }
    out
}

/// A geodesic ball cut from a body: the faces whose three vertices lie within `radius`
/// of `centre` along the edges (Dijkstra), their largest connected part. Unlike a
/// Euclidean ball it does not take in a neighbouring limb.
pub fn geodesic_ball(mesh: &TriMesh, centre: u32, radius: f64) -> TriMesh {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let n = mesh.vertex_count();
    let mut adj: Vec<Vec<u32>> = vec![Vec::new(); n];
    for f in &mesh.faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            adj[a as usize].push(b);
            adj[b as usize].push(a);
        }
    }
    let mut dist = vec![f64::INFINITY; n];
    dist[centre as usize] = 0.0;
    // Distances are non-negative, so their bits order like the values.
    let mut heap = BinaryHeap::from([Reverse((0u64, centre))]);
    while let Some(Reverse((bits, v))) = heap.pop() {
        let d = f64::from_bits(bits);
        if d > dist[v as usize] || d > radius {
            continue;
        }
        for &w in &adj[v as usize] {
            let dw = d + flatcut_mesh::vec3::dist(
                mesh.positions[v as usize],
                mesh.positions[w as usize],
            );
            if dw < dist[w as usize] {
                dist[w as usize] = dw;
                heap.push(Reverse((dw.to_bits(), w)));
            }
        }
    }
    let faces: Vec<u32> = (0..mesh.face_count() as u32)
        .filter(|&f| {
            mesh.faces[f as usize]
                .iter()
                .all(|&v| dist[v as usize] < radius)
        })
        .collect();
    largest_part(mesh, &faces)
}

/// A body patch with one hole: the geodesic ball of `radius` around `centre`
/// ([`geodesic_ball`]) without the faces whose centroids lie within `hole` of it (Euclidean),
/// its largest part; `None` unless that has two boundary loops (the ball a disk, the hole
/// inside it), at most `max_faces` faces and no vertex where two fans touch (the cut's
/// artefact, which `process` refuses with a named error).
pub fn ball_with_hole(
    mesh: &TriMesh,
    centre: u32,
    (radius, hole): (f64, f64),
    max_faces: usize,
) -> Option<TriMesh> {
    let c = mesh.positions[centre as usize];
    let patch = cut(&geodesic_ball(mesh, centre, radius), |p| {
        flatcut_mesh::vec3::dist(p, c) >= hole
    });
    let topo = flatcut_mesh::Topology::build(&patch).ok()?;
    (topo.boundary_loops().len() == 2
        && patch.face_count() <= max_faces
        && topo.non_manifold_vertices().is_empty())
    .then_some(patch)
}

/// Pieces of the MakeHuman body (model units = dm; y up, +z front; MANIFEST landmarks):
/// upper back, chest, left shoulder cap (a ball: two boundary loops), left front thigh.
pub fn body_pieces(body: &TriMesh) -> Vec<(&'static str, TriMesh)> {
    vec![
        (
            "upper back",
            cut(body, |c| {
                c[2] < 0.0 && (3.6..5.4).contains(&c[1]) && c[0].abs() < 1.3
            }),
        ),
        (
            "chest",
            cut(body, |c| {
                c[2] > 0.0 && (3.6..5.2).contains(&c[1]) && c[0].abs() < 1.4
            }),
        ),
        (
            "left shoulder",
            cut(body, |c| {
                let d = [c[0] - 1.68, c[1] - 5.25, c[2] - 0.15];
                (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() < 0.9
            }),
        ),
        (
            "left front thigh",
            cut(body, |c| {
                c[2] > 0.1 && (-3.0..-0.9).contains(&c[1]) && c[0] > 0.3
            }),
        ),
    ]
}

/// Multiplies every coordinate by 1 + k·2.2e-16 (about one ulp), k ∈ {−1, 0, 1} drawn per
/// coordinate from a xorshift sequence of `seed`: an input within round-off of `mesh`, for
/// the round-off sensitivity of the large saddle. Seed 0 leaves `mesh` as it is (the exact
/// grid is the harnesses' seed 0).
pub fn perturb_by_one_ulp(mesh: &mut TriMesh, seed: u64) {
    if seed == 0 {
        return;
    }
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    for p in mesh.positions.iter_mut() {
        for c in p.iter_mut() {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            *c *= 1.0 + ((s % 3) as f64 - 1.0) * 2.2e-16;
        }
    }
}

/// A random piece (`tests/properties.rs`, `measure -- random`): `n`×`n` vertices, interior
/// ones moved by `jitter` (cycled) of the spacing in x and y, on z = Σ c_k m_k(x, y) over the
/// monomials x², xy, y², x³, x²y, xy², y³.
pub fn random_piece(n: usize, jitter: &[(f64, f64)], c: [f64; 7]) -> TriMesh {
    let mut mesh = grid(n, 1.0, |_, _| 0.0);
    let h = 2.0 / (n - 1) as f64;
    let topo = Topology::build(&mesh).unwrap();
    for (v, p) in mesh.positions.iter_mut().enumerate() {
        if topo.is_interior_vertex(VertexId(v as u32)) {
            let (jx, jy) = jitter[v % jitter.len()];
            p[0] += jx * h;
            p[1] += jy * h;
        }
        let (x, y) = (p[0], p[1]);
        let m = [
            x * x,
            x * y,
            y * y,
            x * x * x,
            x * x * y,
            x * y * y,
            y * y * y,
        ];
        p[2] = m.iter().zip(&c).map(|(m, c)| m * c).sum();
    }
    mesh
}

/// Uniform numbers in [0, 1) from a xorshift64 sequence started at `seed` (non-zero): the
/// random corpus of `measure -- random` and the jittered paraboloid, reproducible from the
/// seed.
pub fn uniform(mut s: u64) -> impl FnMut() -> f64 {
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The paraboloid z = a (x² + y²) on [−1, 1]² on an irregular triangulation: the n×n grid
/// with every interior vertex moved in x and y by up to ±`jitter` of the spacing (37 fixed
/// pseudo-random offsets, cycled) before the height is taken. A shallow piece as a scan or a
/// remesher leaves it, where the regular grid's smoothed steps gain nothing
/// (docs/algorithms/flattenable.md, "Irregular shallow pieces: a smoothed jump").
pub fn jittered_paraboloid(n: usize, a: f64, jitter: f64) -> TriMesh {
    let mut next = uniform(0x2545_F491_4F6C_DD1D);
    let offsets: Vec<(f64, f64)> = (0..37)
        .map(|_| (jitter * (2.0 * next() - 1.0), jitter * (2.0 * next() - 1.0)))
        .collect();
    random_piece(n, &offsets, [a, 0.0, a, 0.0, 0.0, 0.0, 0.0])
}

/// One step of Loop subdivision (smooth interior rules, cubic B-spline rules on the
/// boundary): 4× the faces on a smooth surface through the same boundary curve's limit.
/// `measure -- bodies` with `LOOP=k` makes pieces at scan resolution from the bodies' cut
/// pieces this way (a refined copy of a coarse mesh would be piecewise flat, which no scan
/// is). Deterministic: edges and neighbours are visited in sorted order.
pub fn loop_subdivide(mesh: &TriMesh) -> TriMesh {
    use std::collections::BTreeMap;
    let n = mesh.positions.len();
    // Per edge (low, high): the vertices opposite it, one per face.
    let mut opposite: BTreeMap<(u32, u32), Vec<u32>> = BTreeMap::new();
    for f in &mesh.faces {
        for k in 0..3 {
            let (a, b, c) = (f[k], f[(k + 1) % 3], f[(k + 2) % 3]);
            opposite.entry((a.min(b), a.max(b))).or_default().push(c);
        }
    }
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); n];
    let mut boundary_neighbours: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (&(a, b), opp) in &opposite {
        neighbours[a as usize].push(b);
        neighbours[b as usize].push(a);
        if opp.len() == 1 {
            boundary_neighbours[a as usize].push(b);
            boundary_neighbours[b as usize].push(a);
        }
    }
    let p = &mesh.positions;
    let mut positions: Vec<[f64; 3]> = (0..n)
        .map(|v| match boundary_neighbours[v][..] {
            [a, b] => std::array::from_fn(|k| {
                0.75 * p[v][k] + 0.125 * (p[a as usize][k] + p[b as usize][k])
            }),
            _ => {
                let valence = neighbours[v].len() as f64;
                let beta = if neighbours[v].len() == 3 {
                    3.0 / 16.0
                } else {
                    3.0 / (8.0 * valence)
                };
                std::array::from_fn(|k| {
                    let ring: f64 = neighbours[v].iter().map(|&u| p[u as usize][k]).sum();
                    (1.0 - valence * beta) * p[v][k] + beta * ring
                })
            }
        })
        .collect();
    let mut midpoint: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    for (&(a, b), opp) in &opposite {
        let (pa, pb) = (p[a as usize], p[b as usize]);
        let q: [f64; 3] = match opp[..] {
            [c, d] => std::array::from_fn(|k| {
                0.375 * (pa[k] + pb[k]) + 0.125 * (p[c as usize][k] + p[d as usize][k])
            }),
            _ => std::array::from_fn(|k| 0.5 * (pa[k] + pb[k])),
        };
        midpoint.insert((a, b), positions.len() as u32);
        positions.push(q);
    }
    let mid = |a: u32, b: u32| midpoint[&(a.min(b), a.max(b))];
    let faces = mesh
        .faces
        .iter()
        .flat_map(|&[a, b, c]| {
            let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
            [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
        })
        .collect();
    // Per-vertex attributes and face groups of the input would not match the new elements.
    TriMesh {
        positions,
        faces,
        ..TriMesh::default()
    }
}
