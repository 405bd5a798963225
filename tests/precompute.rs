//! The precompute end to end: what it computes (SVCs, fields, which objects get one), that
//! fields agree with rays cast directly, the `.vcuts` file's damage checks, and that a killed
//! run resumes to a byte-identical file; a sharded run gathers to the same bytes, and a gather
//! of an incomplete or mixed set of shards names what is wrong.

use glam::Vec3;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use vcut_cut::Cut;
use vcut_data::file::{Reader, SectionId, SectionKind, Sections, partial_path};
use vcut_data::shard::{GatherError, gather, shard_path};
use vcut_data::{FieldLayout, Precomputed};
use vcut_dirtree::DirectionTree;
use vcut_merge::{MergedCut, merge_weighted_sum};
use vcut_precompute::field::point_visibility;
use vcut_precompute::run::{Job, NoProgress, PrecomputeError, Progress, Summary, precompute, precompute_shard};
use vcut_precompute::{Occluder, PrecomputeParams};
use vcut_scene::{Scene, SceneDesc};
use vcut_tests::scratch;

/// A ball of radius 0.5 floating 1 above a 4 × 4 ground; the ball moves.
const BALL_ABOVE_GROUND: &str = r#"
[environment]
source = "builtin:constant"

[[object]]
name = "ground"
source = "builtin:plane"
size = 4.0
resolution = 16

[[object]]
name = "ball"
source = "builtin:sphere"
size = 0.5
resolution = 12
translation = [0.0, 1.0, 0.0]
moves = true
"#;

fn scene(text: &str) -> Scene {
    let file = Path::new("test.toml");
    SceneDesc::parse(text, file).unwrap().instantiate(Path::new("."), file).unwrap()
}

fn small() -> PrecomputeParams {
    let mut p = PrecomputeParams::fast();
    for (k, v) in [("directions", "1024"), ("field_spheres", "8"), ("field_resolution", "8"), ("svc_chunk", "100")] {
        p.set(k, v).unwrap();
    }
    p
}

fn job<'a>(scene: &'a Scene, params: PrecomputeParams, output: &Path) -> Job<'a> {
    Job {
        scene,
        scene_source: "test.toml".into(),
        environment: "builtin:constant".into(),
        params,
        cache_dir: None,
        output: output.into(),
    }
}

fn run(scene: &Scene, params: PrecomputeParams, output: &Path) -> Summary {
    precompute(&job(scene, params, output), &NoProgress, &AtomicBool::new(false)).unwrap()
}

/// Σ v_k |Ω_k| over a cut.
fn integral(cut: &Cut, tree: &DirectionTree) -> f64 {
    cut.level_order_indices().zip(cut.values()).map(|(k, &v)| f64::from(v) * tree.solid_angle(k)).sum()
}

/// Whether object `o` of the file has no field.
fn data_layout_is_none(file: &Path, o: usize) -> bool {
    Precomputed::open(file).unwrap().layouts[o].is_none()
}

/// One field sphere's cuts and inside marks.
type SphereData = (Vec<Cut>, Vec<bool>);

/// The field of `object` interpolated at `p` (8 samples, trilinear, samples inside the object
/// dropped), expanded to leaves.
fn interpolated(data: &mut Precomputed, object: usize, layout: &FieldLayout, p: Vec3) -> Vec<f32> {
    let mut samples = layout.lookup(p).expect("inside the field");
    let spheres: Vec<(u32, SphereData)> = {
        let mut s: Vec<u32> = samples.iter().map(|x| x.sphere).collect();
        s.dedup();
        s.into_iter().map(|s| (s, data.field_sphere(object, s).unwrap())).collect()
    };
    let sphere = |s: u32| &spheres.iter().find(|(x, _)| *x == s).unwrap().1;
    if FieldLayout::drop_inside(&mut samples, |x| sphere(x.sphere).1[x.point as usize]) == 0 {
        return vec![0.0; data.directions.len()];
    }
    let cuts: Vec<&Cut> = samples.iter().map(|x| &sphere(x.sphere).0[x.point as usize]).collect();
    let weights: Vec<f32> = samples.iter().map(|x| x.weight).collect();
    let mut out = MergedCut::default();
    merge_weighted_sum(&cuts, &weights, &mut out).unwrap();
    out.to_cut().unwrap().expand()
}

#[test]
fn ground_svcs_see_their_whole_hemisphere_and_the_ball_field_holds_its_shadow() {
    let dir = scratch("precompute-ball");
    let out = dir.join("ball.vcuts");
    let s = scene(BALL_ABOVE_GROUND);
    let summary = run(&s, small(), &out);
    // The ball moves, so its shadow on the ground needs a field; the ground is flat and
    // convex, so a frame cuts its shadow on the ball exactly and it gets none.
    assert_eq!(summary.fields, ["ball"]);
    assert!(data_layout_is_none(&out, 0), "no field layout for the ground");
    let mut data = Precomputed::open(&out).unwrap();
    let tree = data.tree().unwrap();
    assert_eq!((data.objects.len(), data.objects[1].name.as_str()), (2, "ball"));
    // Nothing of the ground's own (static) geometry occludes it: every SVC integrates the full
    // cosine lobe, π (the 1,024-direction discretisation and 2^-16 quantisation stay within 1 %).
    for (v, cut) in data.svc_cuts(0).unwrap().iter().enumerate() {
        let i = integral(cut, &tree);
        assert!((i - std::f64::consts::PI).abs() < 0.01 * std::f64::consts::PI, "ground vertex {v}: {i}");
    }
    // The ball's SVCs are those of a convex object: the cosine lobe, unoccluded.
    for cut in data.svc_cuts(1).unwrap() {
        assert!((integral(&cut, &tree) - std::f64::consts::PI).abs() < 0.01 * std::f64::consts::PI);
    }
    // The ball's field at the ground's centre: occluded straight up, visible sideways and down.
    let layout = data.layouts[1].unwrap();
    let below = Vec3::new(0.0, 0.0, 0.0);
    let leaves = interpolated(&mut data, 1, &layout, below);
    let nearest = |d: Vec3| {
        let d = d.normalize();
        (0..tree.leaf_count())
            .max_by(|&a, &b| tree.leaf_directions()[a].dot(d).total_cmp(&tree.leaf_directions()[b].dot(d)))
            .unwrap()
    };
    assert!(leaves[nearest(Vec3::Y)] < 0.05, "up: {}", leaves[nearest(Vec3::Y)]);
    for d in [Vec3::X, Vec3::new(1.0, 0.3, 1.0), Vec3::NEG_Y, Vec3::new(-1.0, 0.2, 0.0)] {
        assert!(leaves[nearest(d)] > 0.95, "{d}: {}", leaves[nearest(d)]);
    }
    // The shadow's solid angle: the field blends the shadows seen from its samples, each a
    // cone of 2π(1 − √(1 − (r/ρ)²)) at distance ρ; radially linear, so coarser than the exact
    // 2π(1 − cos 30°) of this point (1.08 against 0.84 sr with 8 spheres, 1.4r apart).
    let areas: Vec<f64> = (0..tree.leaf_count()).map(|l| tree.solid_angle(tree.index(0, l as u32))).collect();
    let occluded: f64 = leaves.iter().zip(&areas).map(|(v, a)| f64::from(1.0 - v) * a).sum();
    let cone = |rho: f64| 2.0 * std::f64::consts::PI * (1.0 - (1.0 - (0.5 / rho).powi(2)).sqrt());
    let blended: f64 = layout
        .lookup(below)
        .unwrap()
        .iter()
        .map(|x| f64::from(x.weight) * cone(f64::from(layout.sphere_radius(x.sphere))))
        .sum();
    assert!((occluded - blended).abs() < 0.05 * blended, "shadow {occluded} sr, blended samples {blended}");
    let exact = cone(1.0);
    assert!((occluded - exact).abs() < 0.3 * exact, "shadow {occluded} sr, exact {exact}");
}

/// Solid-angle-weighted mean |interpolated field − visibility cast from the point|.
fn field_error_at(data: &mut Precomputed, object: usize, occ: &Occluder, tree: &DirectionTree, p: Vec3) -> f64 {
    let layout = data.layouts[object].unwrap();
    let field = interpolated(data, object, &layout, p);
    let mut direct = vec![0.0f32; tree.leaf_count()];
    point_visibility(occ, tree, p, layout.center, layout.radius, &mut direct);
    let areas: Vec<f64> = (0..tree.leaf_count()).map(|l| tree.solid_angle(tree.index(0, l as u32))).collect();
    field.iter().zip(&direct).zip(&areas).map(|((f, d), a)| f64::from((f - d).abs()) * a).sum::<f64>()
        / (4.0 * std::f64::consts::PI)
}

#[test]
fn a_turnable_precompute_stores_only_cuts_that_turn_and_reads_its_wedged_tree_back() {
    let dir = scratch("precompute-turns");
    let out = dir.join("ball.vcuts");
    let s = scene(BALL_ABOVE_GROUND);
    let mut params = small();
    params.set("turn_steps", "16").unwrap();
    run(&s, params.clone(), &out);
    params.settle();
    let mut data = Precomputed::open(&out).unwrap();
    assert_eq!(data.record.params, params, "turn_steps and turn_bands are recorded");
    let tree = data.tree().unwrap();
    let shape = tree.turn_shape().expect("the file's tree is wedged");
    assert_eq!(Some(shape), params.turn_shape());
    assert_eq!((tree.wedges(), shape.band_height - shape.wedge_height), (16, 4));
    // Every stored cut, SVC and field, turns: none uses a node spanning part of a band.
    let turns = |cut: &Cut| cut.heights().iter().all(|&h| !shape.splits(u32::from(h)));
    for o in 0..2 {
        assert!(data.svc_cuts(o).unwrap().iter().all(turns), "object {o}'s SVCs");
    }
    let layout = data.layouts[1].unwrap();
    for sphere in 0..layout.spheres {
        let (cuts, _) = data.field_sphere(1, sphere).unwrap();
        assert!(cuts.iter().all(turns), "the ball's field, sphere {sphere}");
        // A whole turn returns each cut bit for bit.
        for cut in cuts.iter().take(20) {
            let back = (0..16).fold(cut.clone(), |c, _| c.turned(shape, 1).unwrap());
            assert_eq!(&back, cut);
        }
    }
    // Without turns the file records no turn keys and its tree is the ordinary one.
    let plain = dir.join("plain.vcuts");
    run(&s, small(), &plain);
    let data = Precomputed::open(&plain).unwrap();
    assert_eq!(data.tree().unwrap().turn_shape(), None);
    assert!(!data.record.params.to_toml().contains("turn_"));
}

#[test]
fn a_field_interpolated_at_a_point_agrees_with_rays_cast_from_it() {
    let dir = scratch("precompute-agree");
    let out = dir.join("agree.vcuts");
    let s = scene(BALL_ABOVE_GROUND);
    let mut p = small();
    p.set("field_spheres", "16").unwrap();
    p.set("field_resolution", "16").unwrap();
    run(&s, p, &out);
    let mut data = Precomputed::open(&out).unwrap();
    let tree = data.tree().unwrap();
    let ball = &s.objects[1].mesh;
    let occ = Occluder::new(&[ball]);
    let layout = data.layouts[1].unwrap();
    // Points between samples from just outside the ball to 9r, in scattered directions. The
    // error is the share of the sphere of directions where the interpolated field and rays cast
    // from the point disagree (0 = identical). The field is exact at its samples; between them
    // a shadow's edge and size are blended from the neighbouring samples. With 16 spheres
    // (geometric: 0.97r, 1.26r, 1.65r, 2.15r, … apart by a ratio of 1.3) × 6×16² the bounds are:
    // beyond 2.5r under 1 %, from 1.5r under 5 %, and between the surface and 1.5r under 25 %:
    // there the shadow grows fastest with nearness.
    let mut worst = [0.0f64; 3];
    for k in 0..30 {
        let t = k as f32 / 29.0;
        let d = 1.05 + 7.95 * t * t;
        let dir = Vec3::new((k as f32 * 2.39).cos(), (k as f32 * 1.31).sin(), (k as f32 * 0.77).sin()).normalize();
        let e = field_error_at(&mut data, 1, &occ, &tree, layout.center + dir * d * layout.radius);
        let band = if d >= 2.5 {
            0
        } else if d >= 1.5 {
            1
        } else {
            2
        };
        worst[band] = worst[band].max(e);
    }
    eprintln!("worst disagreement beyond 2.5r, 1.5r..2.5r, surface..1.5r: {worst:?}");
    assert!(worst[0] < 0.01 && worst[1] < 0.05 && worst[2] < 0.25, "worst disagreement by band {worst:?}");
}

#[test]
fn a_scene_with_one_object_or_nothing_moving_builds_no_field() {
    let dir = scratch("precompute-nofield");
    let one = scene("[[object]]\nsource = \"builtin:sphere\"\nresolution = 8\nmoves = true\n");
    let summary = run(&one, small(), &dir.join("one.vcuts"));
    assert!(summary.fields.is_empty());
    let r = Reader::open(&dir.join("one.vcuts")).unwrap();
    assert!(r.entries().iter().all(|e| !matches!(e.id.kind, SectionKind::Field | SectionKind::FieldLayout)));
    // Two static objects: no field, and the ball's shadow is baked into the ground's SVCs.
    let still = scene(&BALL_ABOVE_GROUND.replace("moves = true", "moves = false"));
    let summary = run(&still, small(), &dir.join("still.vcuts"));
    assert!(summary.fields.is_empty());
    let mut data = Precomputed::open(&dir.join("still.vcuts")).unwrap();
    let tree = data.tree().unwrap();
    let ground = data.svc_cuts(0).unwrap();
    let centre = data.objects[0].mesh.positions().iter().position(|p| p.length() < 1e-6).unwrap();
    let lost = std::f64::consts::PI - integral(&ground[centre], &tree);
    // The ball (radius 0.5 at height 1) removes ∫cos over its cone: π sin²30° = π/4.
    assert!((lost - std::f64::consts::PI / 4.0).abs() < 0.1, "baked shadow {lost}");
}

#[test]
fn cut_sizes_shrink_as_thresholds_loosen() {
    let dir = scratch("precompute-monotone");
    let s = scene(&BALL_ABOVE_GROUND.replace("size = 0.5\nresolution = 12", "size = 0.8\nresolution = 16"));
    let mut last = (u64::MAX, u64::MAX);
    for (svc, field) in [("0.0", "0.0"), ("0.002", "0.02"), ("0.01", "0.1"), ("0.05", "0.2")] {
        let mut p = small();
        p.set("svc_max_error", svc).unwrap();
        p.set("field_max_error", field).unwrap();
        p.set("svc_solid_angle_divisor", "1").unwrap();
        let summary = run(&s, p, &dir.join("m.vcuts"));
        let nodes = (summary.sizes[0].nodes, summary.sizes[1].nodes);
        assert!(nodes.0 <= last.0 && nodes.1 <= last.1, "thresholds {svc}/{field}: {nodes:?} after {last:?}");
        last = nodes;
    }
    assert!(last.0 < 1000 * 289 / 4, "loose SVCs are small: {last:?}");
}

#[test]
fn damaged_files_are_refused_naming_the_section() {
    let dir = scratch("precompute-damage");
    let out = dir.join("d.vcuts");
    run(&scene(BALL_ABOVE_GROUND), small(), &out);
    let whole = std::fs::read(&out).unwrap();
    let r = Reader::open(&out).unwrap();
    let field = *r.entries().iter().find(|e| e.id == SectionId::field(1, 3)).unwrap();
    let mesh = *r.entries().iter().find(|e| e.id == SectionId::mesh(0)).unwrap();
    drop(r);
    for (entry, name) in [(field, "section field (object 1, sphere 3)"), (mesh, "section mesh (object 0)")] {
        let mut bad = whole.clone();
        bad[(entry.offset + entry.len / 2) as usize] ^= 0x04;
        std::fs::write(&out, &bad).unwrap();
        let err = match Precomputed::open(&out) {
            Err(e) => e.to_string(),
            Ok(mut d) => d.field_sphere(1, 3).err().map(|e| e.to_string()).unwrap_or_default(),
        };
        assert!(err.contains("d.vcuts") && err.contains(name) && err.contains("checksum"), "{err}");
    }
    for len in [whole.len() - 1, whole.len() - 33, whole.len() / 3, 10] {
        std::fs::write(&out, &whole[..len]).unwrap();
        let err = Precomputed::open(&out).err().unwrap().to_string();
        assert!(err.contains("d.vcuts") && (err.contains("truncated") || err.contains("shorter")), "{len}: {err}");
    }
}

/// Sets `stop` once `after` sections have been computed.
struct KillAfter {
    after: usize,
    computed: AtomicUsize,
    stop: AtomicBool,
}

impl Progress for KillAfter {
    fn section(&self, _: SectionId, resumed: bool) {
        if !resumed && self.computed.fetch_add(1, Ordering::SeqCst) + 1 >= self.after {
            self.stop.store(true, Ordering::SeqCst);
        }
    }
}

#[test]
fn a_killed_run_resumes_to_a_byte_identical_file() {
    let dir = scratch("precompute-resume");
    let s = scene(BALL_ABOVE_GROUND);
    let whole_path = dir.join("whole.vcuts");
    run(&s, small(), &whole_path);
    let whole = std::fs::read(&whole_path).unwrap();
    let out = dir.join("resumed.vcuts");
    // Stop in the SVC stage, then in the field stage, then damage the partial file's tail as a
    // kill mid-write would; each run resumes what the previous one left.
    for after in [2, 6] {
        let kill = KillAfter { after, computed: AtomicUsize::new(0), stop: AtomicBool::new(false) };
        let err = precompute(&job(&s, small(), &out), &kill, &kill.stop).unwrap_err();
        assert!(matches!(err, PrecomputeError::Interrupted { .. }), "{err}");
        assert!(!out.exists() && partial_path(&out).exists());
    }
    let partial = std::fs::read(partial_path(&out)).unwrap();
    std::fs::write(partial_path(&out), &partial[..partial.len() - 5]).unwrap();
    let summary = run(&s, small(), &out);
    let resumed: usize = summary.stages.iter().map(|s| s.resumed).sum();
    assert!(resumed >= 5, "{resumed} sections resumed");
    assert!(std::fs::read(&out).unwrap() == whole, "resumed file differs from an uninterrupted run");
    assert!(!partial_path(&out).exists());
    // Different parameters do not reuse a partial file's sections.
    let kill = KillAfter { after: 3, computed: AtomicUsize::new(0), stop: AtomicBool::new(false) };
    precompute(&job(&s, small(), &out), &kill, &kill.stop).unwrap_err();
    let mut other = small();
    other.set("svc_max_error", "0.02").unwrap();
    let summary = run(&s, other.clone(), &out);
    assert_eq!(summary.stages.iter().map(|s| s.resumed).sum::<usize>(), 0);
    run(&s, other, &whole_path);
    assert!(std::fs::read(&out).unwrap() == std::fs::read(&whole_path).unwrap(), "stale partial sections leaked");
}

/// The ball scene with a second, static ball: three objects, two fields of different sizes.
fn two_balls() -> Scene {
    scene(&format!(
        "{BALL_ABOVE_GROUND}\n[[object]]\nname = \"rock\"\nsource = \"builtin:sphere\"\nsize = 0.3\nresolution = 8\ntranslation = [1.2, 0.3, 0.0]\n"
    ))
}

fn shard(
    s: &Scene,
    params: PrecomputeParams,
    out: &Path,
    index: u32,
    n: u32,
    progress: &dyn Progress,
    stop: &AtomicBool,
) -> Result<Summary, PrecomputeError> {
    let plan = vcut_precompute::plan::plan(s, &params, n).unwrap();
    precompute_shard(&job(s, params, &shard_path(out, index, n)), None, index, &plan, progress, stop)
}

#[test]
fn shards_gather_to_the_one_machine_file_and_a_missing_shard_is_named() {
    let dir = scratch("precompute-shards");
    let s = two_balls();
    let whole_path = dir.join("whole.vcuts");
    run(&s, small(), &whole_path);
    let whole = std::fs::read(&whole_path).unwrap();
    let out = dir.join("sharded.vcuts");
    let n = 3;
    let plan = vcut_precompute::plan::plan(&s, &small(), n).unwrap();
    assert!(plan.loads().iter().all(|&l| l > 0), "every shard has work: {:?}", plan.loads());
    assert!(plan.balance_ratio() < 1.5, "balance {}", plan.balance_ratio());
    // Shard 1 is killed once and resumed, as a requeued array task would be.
    let kill = KillAfter { after: 1, computed: AtomicUsize::new(0), stop: AtomicBool::new(false) };
    let err = shard(&s, small(), &out, 1, n, &kill, &kill.stop).unwrap_err();
    assert!(matches!(err, PrecomputeError::Interrupted { .. }), "{err}");
    // The plan's cost model counts the rays each shard casts (cones, inside points) closely.
    for i in [0, 2] {
        let summary = shard(&s, small(), &out, i, n, &NoProgress, &AtomicBool::new(false)).unwrap();
        let cast: u64 = summary.stages.iter().map(|s| s.rays.rays_cast).sum();
        let planned = plan.loads()[i as usize] as f64;
        assert!((cast as f64 / planned - 1.0).abs() < 0.1, "shard {i}: {cast} rays cast, {planned} planned");
    }
    let files: Vec<_> = (0..n).map(|i| shard_path(&out, i, n)).collect();
    // Shard 1 never finished: the gather names it and the sections it owes, and writes nothing.
    let err = gather(&[files[0].clone(), files[2].clone()], &out).unwrap_err();
    assert_eq!(err.shards_to_rerun(), [1]);
    let owed = plan.sections().iter().filter(|p| p.owner == 1).count();
    let text = err.to_string();
    assert!(text.contains(&format!("shard 1 of 3 owes {owed} sections")), "{text}");
    assert!(!out.exists() && !partial_path(&out).exists());
    // A shard file opens for no renderer.
    let e = Precomputed::open(&files[0]).err().unwrap().to_string();
    assert!(e.contains("shard 0 of 3") && e.contains("--gather"), "{e}");
    let summary = shard(&s, small(), &out, 1, n, &NoProgress, &AtomicBool::new(false)).unwrap();
    assert!(summary.stages.iter().map(|s| s.resumed).sum::<usize>() >= 1);
    let g = gather(&files, &out).unwrap();
    assert_eq!(g.shards, n);
    assert!(std::fs::read(&out).unwrap() == whole, "the gathered file differs from the one-machine run");
    // Twice the same shard, a whole file, shards of other parameters: each refused by name.
    let e = gather(&[files[0].clone(), files[0].clone()], &out).unwrap_err();
    assert!(matches!(e, GatherError::Duplicate { index: 0, .. }), "{e}");
    let e = gather(std::slice::from_ref(&whole_path), &out).unwrap_err();
    assert!(matches!(e, GatherError::NotAShard { .. }) && e.to_string().contains("whole.vcuts"), "{e}");
    let mut other = small();
    other.set("svc_max_error", "0.02").unwrap();
    let other_out = dir.join("other.vcuts");
    shard(&s, other, &other_out, 2, n, &NoProgress, &AtomicBool::new(false)).unwrap();
    let e = gather(&[files[0].clone(), files[1].clone(), shard_path(&other_out, 2, n)], &out).unwrap_err();
    assert!(matches!(e, GatherError::Mismatch { .. }) && e.to_string().contains("section params"), "{e}");
    // A plan of another scene is refused before anything is computed.
    let other_plan = vcut_precompute::plan::plan(&scene(BALL_ABOVE_GROUND), &small(), n).unwrap();
    let e = precompute_shard(
        &job(&s, small(), &dir.join("x.vcuts")),
        None,
        0,
        &other_plan,
        &NoProgress,
        &AtomicBool::new(false),
    )
    .unwrap_err();
    assert!(matches!(e, PrecomputeError::Plan(_)), "{e}");
}

#[test]
fn one_shard_is_the_whole_file_with_its_plan() {
    let dir = scratch("precompute-one-shard");
    let s = scene(BALL_ABOVE_GROUND);
    run(&s, small(), &dir.join("whole.vcuts"));
    let out = dir.join("one.vcuts");
    shard(&s, small(), &out, 0, 1, &NoProgress, &AtomicBool::new(false)).unwrap();
    gather(&[shard_path(&out, 0, 1)], &out).unwrap();
    assert!(std::fs::read(&out).unwrap() == std::fs::read(dir.join("whole.vcuts")).unwrap());
}
