//! Box and bilinear light trees each integrate their map's reconstruction exactly: the root
//! (and every texel's share) against Gauss–Legendre quadrature of the reconstruction's radiance
//! itself, to 1e-6.

use vcut_dirtree::DirectionTree;
use vcut_envmap::procedural::Studio;
use vcut_envmap::{EnvMap, Layout, Reconstruction, layout};
use vcut_lighttree::LightTreeBuilder;
use vcut_sphere::{DirectionSet, RepulsionParams};

/// Gauss–Legendre nodes and weights on [−1, 1], 4 points.
const GL: [(f64, f64); 4] = [
    (-0.861_136_311_594_053, 0.347_854_845_137_454),
    (-0.339_981_043_584_856, 0.652_145_154_862_546),
    (0.339_981_043_584_856, 0.652_145_154_862_546),
    (0.861_136_311_594_053, 0.347_854_845_137_454),
];

/// Sorted, distinct breakpoints in [0, 1].
fn breaks(mut v: Vec<f64>) -> Vec<f64> {
    v.retain(|x| (0.0..=1.0).contains(x));
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-15);
    v
}

/// ∫ L dω of `map`'s reconstruction ([`EnvMap::reconstructed`]) per texel and in all, by 4 × 4
/// Gauss–Legendre over every cell between the texel edges and the reconstruction's nodes
/// (column centres; rows at `j/(h − 1)`), where the integrand is smooth; in f64.
fn quadrature(map: &EnvMap) -> (Vec<[f64; 3]>, [f64; 3]) {
    let Layout::LatLong { width, height } = map.layout() else { panic!("lat-long only") };
    let (w, h) = (f64::from(width), f64::from(height));
    let us = breaks((0..=2 * width).map(|k| f64::from(k) / (2.0 * w)).collect());
    let mut vs: Vec<f64> = (0..=height).map(|j| f64::from(j) / h).collect();
    vs.extend((0..height).map(|k| f64::from(k) / (h - 1.0).max(1.0)));
    let vs = breaks(vs);
    let mut per_texel = vec![[0.0f64; 3]; (width * height) as usize];
    let mut total = [0.0f64; 3];
    for v in vs.windows(2) {
        for u in us.windows(2) {
            let (du, dv) = (u[1] - u[0], v[1] - v[0]);
            let (i, j) = (((u[0] + u[1]) * 0.5 * w) as usize, ((v[0] + v[1]) * 0.5 * h) as usize);
            let texel = &mut per_texel[j * width as usize + i];
            for (a, wa) in GL {
                for (b, wb) in GL {
                    let (uu, vv) = (u[0] + du * 0.5 * (1.0 + a), v[0] + dv * 0.5 * (1.0 + b));
                    let c = map.reconstructed(layout::latlong_dir(uu, vv));
                    // dω = sin θ dθ dφ = 2π² sin(πv) du dv.
                    let jac = 2.0 * std::f64::consts::PI.powi(2) * (std::f64::consts::PI * vv).sin();
                    let f = wa * wb * 0.25 * du * dv * jac;
                    for k in 0..3 {
                        let x = f64::from(c[k]) * f;
                        texel[k] += x;
                        total[k] += x;
                    }
                }
            }
        }
    }
    (per_texel, total)
}

#[test]
fn box_and_bilinear_light_trees_each_integrate_their_reconstruction() {
    let set = DirectionSet::generate(512, &RepulsionParams::default(), |_, _| {}).unwrap();
    let tree = DirectionTree::build(set.directions(), &set.cell_areas()).unwrap();
    let mut builder = LightTreeBuilder::new(&tree);
    // The studio's small bright lights on a 48 × 24 map: where box and bilinear differ most.
    let studio = Studio::default().bake(48);
    let mut totals = Vec::new();
    for r in [Reconstruction::Box, Reconstruction::Bilinear] {
        let map = studio.clone().with_reconstruction(r).unwrap();
        let (per_texel, want) = quadrature(&map);
        // Each texel's mean × solid angle is its share of the reconstruction's integral.
        let mut texel = 0;
        map.for_each_patch(1, |_, omega, c| {
            for k in 0..3 {
                let got = f64::from(c[k]) * omega;
                let q = per_texel[texel][k];
                assert!((got - q).abs() <= 1e-6 * want[k].max(1e-12), "{r:?} texel {texel}: {got} vs {q}");
            }
            texel += 1;
        });
        for (name, tree) in [("build", builder.build(&map)), ("build_exact", builder.build_exact(&map, 2))] {
            let root = tree.root();
            for k in 0..3 {
                let rel = (root[k] - want[k]).abs() / want[k];
                println!("{r:?} {name}: root {:.9} vs quadrature {:.9}, rel {rel:.2e}", root[k], want[k]);
                assert!(rel < 1e-6, "{r:?} {name} channel {k}: {} vs {}", root[k], want[k]);
            }
        }
        totals.push(want);
    }
    // Not the same integral: the reconstructions differ on this map.
    let diff = (totals[0][1] - totals[1][1]).abs() / totals[0][1];
    println!("box vs bilinear: {:.3} % of the power", diff * 100.0);
    assert!(diff > 1e-4, "{diff}");
}

#[test]
fn a_cube_map_refuses_bilinear_reconstruction_by_name() {
    let cube = EnvMap::new(
        Layout::Cube { size: 2, handedness: vcut_envmap::CubeHandedness::Literal },
        vec![[1.0; 3]; 24],
        "probe-cube",
        vcut_envmap::InvalidTexels::Reject,
    )
    .unwrap()
    .0;
    let e = cube.with_reconstruction(Reconstruction::Bilinear).unwrap_err().to_string();
    assert!(e.contains("probe-cube") && e.contains("lat-long"), "{e}");
}
