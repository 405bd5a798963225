//! Where a frame's error against the exact-direction reference comes from, per object:
//!
//! - `frame`: the frame as rendered (SVC × interpolated fields, merged, shaded);
//! - `exact_fields`: the SVC times each field's exact cut at the vertex itself (no trilinear
//!   interpolation between field samples) and each flat object's cut (exact in the frame too),
//!   shaded the same way: what denser fields could reach;
//! - `exact_visibility`: the frame's merged cut with every node's value replaced by the exact
//!   mean of V·max(0, n·ω) over its leaves: the clustering error alone.
//!
//! `cargo run --release -p vcut-benches --example error_sources -- FILE.vcuts [--env builtin:constant|MAP]
//! [--eye X,Y,Z] [--move OBJECT=DX,DY,DZ] [--scene SPEC]` prints `key=value` lines (`--scene
//! builtin:teapot`: that scene's environment and camera, the frame `cargo xtask bench` measures). With `--bins` it prints
//! instead, per object, where the frame's squared error is: the share of its worst 1/5/20 % of
//! vertices, shares by distance to the nearest field source (in its radii) and near a cube-map
//! edge or not, and the 12 worst vertices with their field sources.
//!
//! With `--layouts 32x32,64x32,128x64` it prints instead the frame's error as if every field
//! had that many spheres of 6×R² points (same radii and spacing; exact cuts computed only at
//! the samples the vertices need, interpolated and merged as the frame does): how much denser
//! fields would have to be for a given error, without precomputing them. `32x32` (the paper
//! preset) reproduces the frame's own error; `32x32i0.05` also moves the innermost sphere to
//! 0.05r (the paper: 0.2r; within it lookups clamp to it); `32x32i0.05@ground` changes only the
//! object `ground`'s field (the others keep the file's layouts). With `--inside-surface` a
//! sample inside its object takes the cut where its radial line leaves the object instead of
//! one fully occluded node (the frame's `InsideSamples::Occluded`).
//!
//! The cuts carry all the light here, the sun's too, as in the paper: this is about the cuts'
//! error. `--sun-rays` keeps the frame's default instead, the sun's leaves cast by rays.

use glam::Vec3;
use rayon::prelude::*;
use std::path::Path;
use vcut_data::Precomputed;
use vcut_envmap::{EnvMap, procedural};
use vcut_merge::{MergedCut, merge_product};
use vcut_precompute::Occluder;
use vcut_precompute::field::exact_point_cut;
use vcut_precompute::svc::leaf_visibility;
use vcut_scene::Mesh;
use vcut_shade::Frame;
use vcut_shade::reference::{errors, exact_direction};

fn vec3(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> =
        s.split(',').map(|x| x.trim().parse::<f32>().map_err(|e| format!("{s}: {e}"))).collect::<Result<_, _>>()?;
    match v.as_slice() {
        [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
        _ => Err(format!("{s}: expected X,Y,Z")),
    }
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let file = args.first().ok_or(
        "usage: error_sources FILE.vcuts [--env builtin:sky|builtin:constant|MAP] [--eye X,Y,Z] [--move OBJECT=DX,DY,DZ] [--scene SPEC] [--sun-rays] [--bins | --layouts SxR[iINNER][@OBJECT],... [--inside-surface]]",
    )?;
    let bins_only = args.iter().any(|a| a == "--bins");
    let option = |name: &str| args.iter().position(|a| a == name).and_then(|i| args.get(i + 1)).cloned();
    // `--scene SPEC`: the scene's environment and first camera (the bench's frame).
    let scene = option("--scene").map(|s| vcut_scene::Scene::open(&s).map_err(|e| e.to_string())).transpose()?;
    let env = match (option("--env").as_deref(), &scene) {
        (None, Some(scene)) => scene.environment.clone(),
        (None | Some("builtin:sky"), _) => procedural::PreethamSky::default().bake(1024),
        (Some("builtin:constant"), _) => EnvMap::constant([1.0; 3]),
        (Some(path), _) => {
            vcut_envmap::load(Path::new(path), vcut_envmap::InvalidTexels::Reject)
                .map_err(|e| format!("--env {path}: {e}"))?
                .0
        }
    };
    let scene_eye = scene.as_ref().and_then(|s| s.cameras.first()).map(|c| c.position);
    let eye = option("--eye").map(|e| vec3(&e)).transpose()?.or(scene_eye).unwrap_or(Vec3::new(0.0, 2.0, 6.0));
    let mut data = Precomputed::open(Path::new(file)).map_err(|e| e.to_string())?;
    let offset = data.svc_origin_offset();
    // The sun through the cuts, as the paper, unless `--sun-rays`.
    let settings = vcut_shade::FrameSettings { sun_rays: args.iter().any(|a| a == "--sun-rays"), ..Default::default() };
    let mut frame = Frame::open(&mut data, &env, &settings, None).map_err(|e| e.to_string())?;
    if let Some(m) = option("--move") {
        let (name, d) = m.split_once('=').ok_or("--move OBJECT=DX,DY,DZ")?;
        let o = frame.object_index(name).ok_or(format!("no object {name}"))?;
        frame.translate(o, vec3(d)?).map_err(|e| e.to_string())?;
    }
    let shaded = frame.shade(eye);
    let exact = exact_direction(&frame, eye, offset);
    let meshes: Vec<Mesh> = (0..frame.object_count())
        .map(|o| {
            let vcut_shade::FrameObject { mesh: m, .. } = frame.object(o);
            Mesh::from_valid_parts(frame.object(o).positions(), m.normals().to_vec(), m.triangles().to_vec())
                .map_err(|e| e.to_string())
        })
        .collect::<Result<_, _>>()?;
    let all = Occluder::new(&meshes.iter().collect::<Vec<_>>());
    let alone: Vec<Occluder> = meshes.iter().map(|m| Occluder::new(&[m])).collect();
    let tree = frame.tree();
    if let Some(specs) = option("--layouts") {
        let surface = args.iter().any(|a| a == "--inside-surface");
        println!("frame all={:.4}", errors(&shaded, &exact).0);
        for spec in specs.split(',') {
            let (body, only) = match spec.split_once('@') {
                Some((b, name)) => {
                    (b, Some(frame.object_index(name).ok_or(format!("--layouts {spec}: no object {name}"))?))
                }
                None => (spec, None),
            };
            let (s, rest) =
                body.split_once('x').ok_or(format!("--layouts {spec}: SPHERESxRESOLUTION[iINNER][@OBJECT]"))?;
            let (r, inner) = match rest.split_once('i') {
                Some((r, i)) => {
                    let inner = i.parse::<f32>().ok().filter(|x| *x > 0.0).ok_or(format!("--layouts {spec}: {i}"))?;
                    (r, Some(inner))
                }
                None => (rest, None),
            };
            let parse = |x: &str| x.parse::<u32>().ok().filter(|&n| n >= 1).ok_or(format!("--layouts {spec}: {x}"));
            let got = layout_frame(&frame, &alone, eye, parse(s)?, parse(r)?, inner, only, surface);
            let per: Vec<String> = (0..frame.object_count())
                .map(|o| format!("{}={:.4}", frame.object(o).name, errors(&[got[o].clone()], &[exact[o].clone()]).0))
                .collect();
            println!("layout={spec} all={:.4} {}", errors(&got, &exact).0, per.join(" "));
        }
        return Ok(());
    }
    let (mut fields_all, mut vis_all) = (Vec::new(), Vec::new());
    for o in 0..frame.object_count() {
        let positions = frame.object(o).positions();
        let radius = frame.object(o).mesh.bounds().radius;
        if bins_only {
            bins(&frame, o, &positions, &shaded[o], &exact[o]);
            continue;
        }
        let rows: Vec<(Vec3, Vec3)> = (0..positions.len())
            .into_par_iter()
            .map(|v| {
                let x = positions[v];
                // SVC × exact field cuts at x.
                let mut cuts = vec![frame.svc(o, v).unwrap_or_else(|e| panic!("vertex {v}: {e}"))];
                for (j, layout) in frame.field_sources(o, v) {
                    let centre = layout.center + frame.object(j).translation;
                    cuts.push(exact_point_cut(&alone[j], tree, x, centre, layout.radius).0);
                }
                cuts.extend(flat_cuts(&frame, o, v));
                let mut product = MergedCut::default();
                merge_product(&cuts.iter().collect::<Vec<_>>(), &mut product).unwrap_or_else(|e| panic!("{e}"));
                // The frame's cut with exact node means.
                let n = frame.object(o).mesh.normals()[v];
                let mut leaves = vec![0.0f32; tree.leaf_count()];
                leaf_visibility(&all, tree, x + n * offset * radius, n, &mut leaves);
                // Merged at setup, so merging it again cannot fail.
                let mut means = frame.merged(o, v).expect("merged at setup").into_owned();
                let heights = means.heights.clone();
                let mut leaf = 0usize;
                for (value, &h) in means.values.iter_mut().zip(&heights) {
                    let w = 1usize << h;
                    *value = leaves[leaf..leaf + w].iter().sum::<f32>() / w as f32;
                    leaf += w;
                }
                (frame.shade_cut(o, v, &product, eye), frame.shade_cut_means(o, v, &means, eye))
            })
            .collect();
        let fields: Vec<Vec3> = rows.iter().map(|r| r.0).collect();
        let vis: Vec<Vec3> = rows.iter().map(|r| r.1).collect();
        let e = |got: &[Vec3]| errors(&[got.to_vec()], &[exact[o].clone()]).0;
        println!(
            "object={} frame={:.4} exact_fields={:.4} exact_visibility={:.4}",
            frame.object(o).name,
            e(&shaded[o]),
            e(&fields),
            e(&vis)
        );
        fields_all.push(fields);
        vis_all.push(vis);
    }
    if bins_only {
        return Ok(());
    }
    println!(
        "object=all frame={:.4} exact_fields={:.4} exact_visibility={:.4}",
        errors(&shaded, &exact).0,
        errors(&fields_all, &exact).0,
        errors(&vis_all, &exact).0
    );
    Ok(())
}

/// The frame shaded as if every field had `spheres` spheres of 6×`resolution`² points (the
/// same radii range, or `inner`·r inward, and spacing): each sample an exact cut, computed only where a vertex needs
/// it, interpolated and merged with the SVC as the frame does (samples inside an object blend
/// in as occluded, or with `surface` as the cut where their radial line leaves it).
#[allow(clippy::too_many_arguments)]
fn layout_frame(
    frame: &Frame,
    alone: &[Occluder],
    eye: Vec3,
    spheres: u32,
    resolution: u32,
    inner: Option<f32>,
    only: Option<usize>,
    surface: bool,
) -> Vec<Vec<Vec3>> {
    use std::collections::HashMap;
    use vcut_merge::{Group, merge};
    let tree = frame.tree();
    let layout_of = |j: usize, l: vcut_data::FieldLayout| {
        if only.is_some_and(|o| o != j) {
            return l;
        }
        vcut_data::FieldLayout { spheres, resolution, inner: inner.unwrap_or(l.inner), ..l }
    };
    // Every (object, sphere, point) a vertex needs, once.
    let mut wanted: Vec<(usize, u32, u32)> = Vec::new();
    let mut layouts: HashMap<usize, vcut_data::FieldLayout> = HashMap::new();
    for o in 0..frame.object_count() {
        let positions = frame.object(o).positions();
        for (v, &x) in positions.iter().enumerate() {
            for (j, layout) in frame.field_sources(o, v) {
                let l = layout_of(j, layout);
                layouts.insert(j, l);
                if let Some(samples) = l.lookup(x - frame.object(j).translation) {
                    wanted.extend(samples.iter().filter(|x| x.weight > 0.0).map(|x| (j, x.sphere, x.point)));
                }
            }
        }
    }
    wanted.sort_unstable();
    wanted.dedup();
    let cuts: Vec<vcut_cut::Cut> = wanted
        .par_iter()
        .map(|&(j, s, i)| {
            let l = layouts[&j];
            let t = frame.object(j).translation;
            let p = l.point(s, i) + t;
            if alone[j].inside(p) && surface {
                // The cut where the sample's radial line leaves the object.
                let c = l.center + t;
                let d = (p - c).normalize_or(Vec3::Y);
                let step = 0.005 * l.radius;
                let mut q = p;
                while alone[j].inside(q) && (q - c).length() < l.outer * l.radius {
                    q += d * step;
                }
                exact_point_cut(&alone[j], tree, q + d * step, c, l.radius).0
            } else if alone[j].inside(p) {
                vcut_cut::Cut::root(tree.height(), 0.0).unwrap_or_else(|e| unreachable!("{e}"))
            } else {
                exact_point_cut(&alone[j], tree, p, l.center + t, l.radius).0
            }
        })
        .collect();
    let index: HashMap<(usize, u32, u32), usize> = wanted.iter().enumerate().map(|(k, &w)| (w, k)).collect();
    (0..frame.object_count())
        .map(|o| {
            let positions = frame.object(o).positions();
            (0..positions.len())
                .into_par_iter()
                .map(|v| {
                    let svc = frame.svc(o, v).unwrap_or_else(|e| panic!("vertex {v}: {e}"));
                    let svc_ref = &svc;
                    let mut factors: Vec<(Vec<&vcut_cut::Cut>, Vec<f32>)> = Vec::new();
                    for (j, layout) in frame.field_sources(o, v) {
                        let Some(samples) = layout_of(j, layout).lookup(positions[v] - frame.object(j).translation)
                        else {
                            continue;
                        };
                        let kept: Vec<_> = samples.iter().filter(|x| x.weight > 0.0).collect();
                        factors.push((
                            kept.iter().map(|x| &cuts[index[&(j, x.sphere, x.point)]]).collect(),
                            kept.iter().map(|x| x.weight).collect(),
                        ));
                    }
                    let flats = flat_cuts(frame, o, v);
                    factors.extend(flats.iter().map(|c| (vec![c], vec![1.0])));
                    let mut groups = vec![Group::single(&svc_ref)];
                    groups.extend(factors.iter().map(|(c, w)| Group { cuts: c, weights: w }));
                    let mut out = MergedCut::default();
                    merge(&groups, &mut out).unwrap_or_else(|e| panic!("{e}"));
                    frame.shade_cut(o, v, &out, eye)
                })
                .collect()
        })
        .collect()
}

/// The exact cuts of the flat convex objects that shadow vertex `v` of object `o`, as the
/// frame merges them (a flat object has no field to interpolate).
fn flat_cuts(frame: &Frame, o: usize, v: usize) -> Vec<vcut_cut::Cut> {
    frame.flat_sources(o, v).into_iter().filter_map(|(j, at)| frame.flat_cut(j, at)).collect()
}

/// Shares of an object's squared error by where its vertices sit in the fields around them.
fn bins(frame: &Frame, o: usize, positions: &[Vec3], got: &[Vec3], exact: &[Vec3]) {
    let total: f32 = got.iter().zip(exact).map(|(g, e)| (*g - *e).length_squared()).sum();
    let norm: f32 = exact.iter().map(|e| e.length_squared()).sum();
    let mut by_radius = [0.0f32; 8];
    let mut by_edge = [0.0f32; 2];
    let mut counts_r = [0usize; 8];
    let mut counts_e = [0usize; 2];
    let mut errs: Vec<f32> = Vec::new();
    for v in 0..positions.len() {
        let err = (got[v] - exact[v]).length_squared();
        errs.push(err);
        let mut best: Option<(f32, bool)> = None;
        for (j, layout) in frame.field_sources(o, v) {
            let d = positions[v] - (layout.center + frame.object(j).translation);
            let t = d.length() / layout.radius;
            let a = d.abs();
            let m = a.max_element();
            let (x, y) = if m == a.x {
                (a.y, a.z)
            } else if m == a.y {
                (a.x, a.z)
            } else {
                (a.x, a.y)
            };
            let lim = 1.0 - 1.0 / layout.resolution as f32;
            let edge = x / m > lim || y / m > lim;
            if best.is_none_or(|b| t < b.0) {
                best = Some((t, edge));
            }
        }
        let Some((t, edge)) = best else { continue };
        let b = [0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 3.0, f32::MAX].iter().position(|&x| t < x).unwrap();
        by_radius[b] += err;
        counts_r[b] += 1;
        by_edge[edge as usize] += err;
        counts_e[edge as usize] += 1;
    }
    let mut order: Vec<usize> = (0..errs.len()).collect();
    order.sort_by(|&a, &b| errs[b].total_cmp(&errs[a]));
    for &v in order.iter().take(12) {
        let srcs: Vec<String> = frame
            .field_sources(o, v)
            .iter()
            .map(|(j, l)| {
                let d = positions[v] - (l.center + frame.object(*j).translation);
                format!("{}@{:.3}r", frame.object(*j).name, d.length() / l.radius)
            })
            .collect();
        println!(
            "  worst v={v} p={:.3?} got={:.3?} exact={:.3?} share={:.3} fields={:?}",
            positions[v],
            got[v],
            exact[v],
            errs[v] / total,
            srcs
        );
    }
    errs.sort_by(|a, b| b.total_cmp(a));
    let top = |f: f32| errs[..((errs.len() as f32 * f) as usize).max(1)].iter().sum::<f32>() / total;
    println!(
        "bins object={} rel_l2={:.4} top1%={:.3} top5%={:.3} top20%={:.3}",
        frame.object(o).name,
        (total / norm).sqrt(),
        top(0.01),
        top(0.05),
        top(0.2)
    );
    for (i, x) in ["<0.5r", "<0.75r", "<1r", "<1.25r", "<1.5r", "<2r", "<3r", ">=3r"].iter().enumerate() {
        println!("  radius {x}: vertices={} share={:.3}", counts_r[i], by_radius[i] / total);
    }
    println!(
        "  cube edge band: vertices={} share={:.3}; interior vertices={} share={:.3}",
        counts_e[1],
        by_edge[1] / total,
        counts_e[0],
        by_edge[0] / total
    );
}
