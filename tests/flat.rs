//! Flat convex occluders: a ground plane gets no field, and a frame multiplies each vertex's
//! SVC by the ground's exact cut at it ([`vcut_shade::flat`]) — at rest and after any move.

use glam::Vec3;
use vcut_data::Precomputed;
use vcut_envmap::EnvMap;
use vcut_shade::Frame;
use vcut_shade::reference::{errors, exact_direction};

/// A ball resting on a ground plane (it touches it) and free to move.
const BALL_ON_GROUND: &str = r#"
[[object]]
name = "ground"
source = "builtin:plane"
size = 4.0
resolution = 12

[[object]]
name = "ball"
source = "builtin:sphere"
size = 0.5
resolution = 16
translation = [0.0, 0.5, 0.0]
moves = true
"#;

/// The scene precomputed in scratch directory `name`, its frame merging every move at once with
/// the sun through the cuts; with the rays' origin offset and the ball's and ground's indices.
fn frame(name: &str) -> (Frame, f32, usize, usize) {
    let out = vcut_tests::scratch(name).join("ball.vcuts");
    let params = [("directions", "2048"), ("field_spheres", "8"), ("field_resolution", "8")];
    let summary = vcut_tests::precompute_text(BALL_ON_GROUND, &params, &out);
    assert_eq!(summary.fields, ["ball"], "the flat ground gets no field");
    let mut data = Precomputed::open(&out).unwrap();
    let offset = data.svc_origin_offset();
    let settings = vcut_shade::FrameSettings { deferred_merges: false, sun_rays: false, ..Default::default() };
    let frame = Frame::open(&mut data, &EnvMap::constant([1.0; 3]), &settings, None).unwrap();
    let (ball, ground) = (frame.object_index("ball").unwrap(), frame.object_index("ground").unwrap());
    (frame, offset, ball, ground)
}

/// Every ball vertex's merged cut is its SVC times the ground's exact cut where its rays start
/// (leaf by leaf), for the vertices the ground can shadow; the others are their SVC alone.
fn check_products(frame: &Frame, ball: usize, ground: usize) -> usize {
    let mut shadowed = 0;
    for v in 0..frame.object(ball).mesh.vertex_count() {
        let merged = frame.merged(ball, v).unwrap().to_cut().unwrap().expand();
        let mut product = frame.svc(ball, v).unwrap().expand();
        let sources = frame.flat_sources(ball, v);
        assert!(frame.field_sources(ball, v).is_empty(), "the ground has no field");
        if let Some(&(j, at)) = sources.first() {
            assert_eq!((j, sources.len()), (ground, 1));
            for (p, g) in product.iter_mut().zip(frame.flat_cut(ground, at).unwrap().expand()) {
                *p *= g;
            }
            shadowed += 1;
        }
        assert_eq!(merged, product, "vertex {v}");
    }
    shadowed
}

#[test]
fn a_flat_ground_shadows_a_moving_ball_by_its_exact_cut() {
    let (mut frame, offset, ball, ground) = frame("flat");
    let n = frame.object(ball).mesh.vertex_count();
    let eye = Vec3::new(3.0, 4.0, 5.0);
    let mut worst: f64 = 0.0;
    for (step, at) in [Vec3::ZERO, Vec3::new(0.6, 0.0, 0.3), Vec3::new(1.45, 0.2, -1.2)].into_iter().enumerate() {
        frame.translate(ball, at).unwrap();
        // The ground lies wholly below the horizon of the vertices near the top only.
        let shadowed = check_products(&frame, ball, ground);
        assert!(shadowed > n / 2 && shadowed < n, "step {step}: {shadowed} of {n}");
        let shaded = frame.shade(eye);
        let exact = exact_direction(&frame, eye, offset);
        let (ball_error, _) = errors(&[shaded[ball].clone()], &[exact[ball].clone()]);
        worst = worst.max(ball_error);
    }
    // What is left is the clustering of 2,048 directions and the SVCs' own error.
    println!("the ball's worst error against the exact reference: {worst}");
    assert!(worst < 0.02, "the ball errs {worst} against the exact reference");
}

/// The frame's `flat_edge_leaves` set to `n`; returns the vertices merged.
fn set_edges(frame: &mut Frame, n: u32) -> Result<usize, vcut_shade::FrameError> {
    let settings =
        vcut_shade::FrameSettings { flat_edge_leaves: vcut_shade::FlatEdges::Leaves(n), ..frame.settings().clone() };
    frame.reconfigure(&settings)
}

/// `FrameSettings::flat_edge_leaves`: the ground's cut estimated across its edges in nodes of up
/// to 16 leaves re-merges exactly the vertices the ground shadows, keeps every merged cut the
/// SVC times the (estimated) ground cut, moves included, changes the image a little, and 1
/// gives back the exact cut's image bit for bit.
#[test]
fn a_ground_estimated_across_its_edges_re_merges_what_it_shadows() {
    let (mut frame, offset, ball, ground) = frame("flat-edges");
    let eye = Vec3::new(3.0, 4.0, 5.0);
    frame.translate(ball, Vec3::new(0.6, 0.0, 0.3)).unwrap();
    let exact_image = frame.shade(eye);
    let reference = exact_direction(&frame, eye, offset);
    let (exact_error, _) = errors(&exact_image, &reference);
    for bad in [0, 3, 4096] {
        let err = set_edges(&mut frame, bad).unwrap_err().to_string();
        assert!(err.contains("flat_edge_leaves") && err.contains(&bad.to_string()), "{err}");
    }
    let shadowed = check_products(&frame, ball, ground);
    assert_eq!(set_edges(&mut frame, 16).unwrap(), shadowed);
    assert_eq!(set_edges(&mut frame, 16).unwrap(), 0, "unchanged: nothing to merge");
    assert_eq!(check_products(&frame, ball, ground), shadowed);
    let image = frame.shade(eye);
    let (error, _) = errors(&image, &reference);
    assert_ne!(image, exact_image);
    assert!((error - exact_error).abs() < 0.002, "error {error}, exact cut's {exact_error}");
    // A move keeps the estimate.
    frame.translate(ball, Vec3::new(1.0, 0.0, -0.4)).unwrap();
    check_products(&frame, ball, ground);
    frame.translate(ball, Vec3::new(0.6, 0.0, 0.3)).unwrap();
    // The interactive setting: 1/256 of the 2,048 directions.
    assert_eq!(vcut_shade::FlatEdges::Interactive.leaves(frame.tree().leaf_count()), 8);
    assert_eq!(set_edges(&mut frame, 8).unwrap(), shadowed);
    let (error, _) = errors(&frame.shade(eye), &reference);
    assert!((error - exact_error).abs() < 0.002, "error {error}, exact cut's {exact_error}");
    assert_eq!(set_edges(&mut frame, 1).unwrap(), shadowed);
    assert_eq!(frame.shade(eye), exact_image);
}
