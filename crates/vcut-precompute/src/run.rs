//! The whole precompute: directions and tree, SVCs of every object, fields of the objects that
//! need one, streamed section by section into a `.vcuts` file that a later run resumes.
//!
//! **What is computed.** An object's SVC holds what never moves relative to its vertices: its
//! own geometry if it is movable; if it is static, its own geometry *and every other static
//! object* (static–static shadows are baked, so frames never merge fields for them). Object X
//! gets a field when some other object Y exists with X or Y movable: only then does anything
//! move relative to X. A scene with one object, or with nothing movable, builds no field. Nor
//! does a flat convex object ([`vcut_scene::flat::FlatOutline`]: a ground plane, a floor): a
//! frame cuts its shadow exactly at each vertex instead.
//!
//! **Order.** `params`, `directions`, one `mesh` per object, one `field-layout` per field, the
//! `svc` chunks (`svc_chunk` vertices each), then one `field` section per sphere. Each section is
//! deterministic (parallel work is collected in order), so a resumed file is byte-identical.
//!
//! **Shards.** [`precompute_shard`] writes the same header sections, a `shard` section (its
//! index and the plan, [`crate::plan`]), and only the cut sections the plan gives it; gathering
//! every shard's file ([`vcut_data::shard::gather`]) gives this run's file byte for byte.

use crate::field::sphere_cuts;
use crate::params::PrecomputeParams;
use crate::plan::CutSection;
use crate::setup::Setup;
use crate::{Occluder, RayStats, cone_outside, visit_leaves};
use glam::Vec3;
use rayon::prelude::*;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use vcut_cut::codec::{self, ShapeCoding, ValueFormat};
use vcut_data::file::{FileError, Reader, SectionId, SectionKind, Sections, Writer};
use vcut_data::shard::ShardPlan;
use vcut_data::{FieldLayout, sections};
use vcut_dirtree::DirectionTree;
use vcut_scene::flat::FlatOutline;
use vcut_scene::{Motion, Scene};
use vcut_sphere::{DirectionSet, RepulsionParams};

/// What to precompute.
pub struct Job<'a> {
    /// The scene (objects at rest).
    pub scene: &'a Scene,
    /// Where the scene came from (`builtin:teapot`, a file), recorded in the output.
    pub scene_source: String,
    /// The environment the user named, recorded for the renderer (the precompute does not
    /// depend on lighting).
    pub environment: String,
    /// Parameters.
    pub params: PrecomputeParams,
    /// Direction-set cache folder (`None`: generate every time).
    pub cache_dir: Option<PathBuf>,
    /// The output file.
    pub output: PathBuf,
}

/// Receives progress; every method has a default that ignores it. Called from worker threads.
pub trait Progress: Sync {
    /// A stage starts with `total` units of work (vertices or sample points).
    fn stage(&self, _name: &str, _total: u64) {}
    /// `n` more units are done.
    fn advance(&self, _n: u64) {}
    /// A section was written (`resumed`: kept from a previous run).
    fn section(&self, _id: SectionId, _resumed: bool) {}
    /// The current stage is over.
    fn end_stage(&self) {}
}

/// Ignores progress.
pub struct NoProgress;
impl Progress for NoProgress {}

/// Why the precompute stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PrecomputeError {
    /// Reading or writing the output failed.
    #[error(transparent)]
    File(#[from] FileError),
    /// The direction set could not be made.
    #[error("directions: {0}")]
    Directions(#[from] vcut_sphere::SphereError),
    /// The direction tree could not be built over the set.
    #[error("direction tree: {0}")]
    Tree(#[from] vcut_dirtree::TreeError),
    /// Bad parameters.
    #[error(transparent)]
    Params(#[from] crate::params::ParamError),
    /// A shard's plan is unusable, or not the plan of this scene and these parameters.
    #[error("shard plan: {0}")]
    Plan(String),
    /// A cut did not encode (a value outside the chosen format's range).
    #[error("{section}: {error}")]
    Encode {
        /// Section.
        section: String,
        /// What failed.
        error: vcut_cut::codec::EncodeError,
    },
    /// The scene cannot be precomputed.
    #[error("scene {scene}: {reason}")]
    Scene {
        /// The scene's source.
        scene: String,
        /// What is wrong.
        reason: String,
    },
    /// `interrupt` was set: the finished sections are in `<output>.partial` and the next run
    /// resumes from them.
    #[error("interrupted; {sections} sections kept in {} for the next run to resume", partial.display())]
    Interrupted {
        /// The partial file.
        partial: PathBuf,
        /// Sections it holds.
        sections: usize,
    },
}

/// One stage's figures.
#[derive(Debug, Clone, PartialEq)]
pub struct StageSummary {
    /// `directions`, `svc` or `fields`.
    pub name: &'static str,
    /// Wall time in seconds (this run).
    pub seconds: f64,
    /// Rays cast and directions resolved without rays (this run; resumed sections count none).
    pub rays: RayStats,
    /// Seconds spent in sections computed this run (ray casting, cut selection, encoding).
    pub compute_seconds: f64,
    /// Raw occlusion rays/s on a sample of this stage's own rays (every 61st vertex or point of
    /// each section computed this run), same occluders, interleaved with the stage.
    pub raw_rays_per_second: f64,
    /// Sections computed this run.
    pub computed: usize,
    /// Sections kept from a previous run.
    pub resumed: usize,
}

impl StageSummary {
    fn new(name: &'static str) -> StageSummary {
        StageSummary {
            name,
            seconds: 0.0,
            rays: RayStats::default(),
            compute_seconds: 0.0,
            raw_rays_per_second: 0.0,
            computed: 0,
            resumed: 0,
        }
    }

    /// Keeps section `id` from the partial file if it is the next one there (counting it and
    /// reporting its `units` of work as done); returns whether it was kept.
    fn try_keep(
        &mut self,
        writer: &mut Writer,
        id: SectionId,
        units: u64,
        progress: &dyn Progress,
    ) -> Result<bool, FileError> {
        if !writer.can_keep(id) {
            return Ok(false);
        }
        writer.keep(id)?;
        self.resumed += 1;
        progress.advance(units);
        progress.section(id, true);
        Ok(true)
    }

    /// Rays cast per second of compute (0 when nothing was cast).
    pub fn rays_per_second(&self) -> f64 {
        if self.compute_seconds > 0.0 { self.rays.rays_cast as f64 / self.compute_seconds } else { 0.0 }
    }
}

/// Sizes of one kind of cut section, in the file's height codec and in the index baseline.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CutSizes {
    /// `svc` or `field`.
    pub kind: &'static str,
    /// Sections.
    pub sections: usize,
    /// Cuts.
    pub cuts: u64,
    /// Nodes over all cuts.
    pub nodes: u64,
    /// Largest cut.
    pub max_nodes: u64,
    /// Payload bytes in the file (its shape coding and value format, offsets included).
    pub bytes: u64,
    /// The same cuts in the paper's height codec (4/5-bit heights) with the file's value format.
    pub heights_codec_bytes: u64,
    /// The same cuts as node index (u16/u32) + f32 value, with the same offsets.
    pub index_baseline_bytes: u64,
}

/// What a run did and wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Per stage.
    pub stages: Vec<StageSummary>,
    /// SVC and field sizes.
    pub sizes: Vec<CutSizes>,
    /// Final file size.
    pub file_bytes: u64,
    /// Objects with a field, by name.
    pub fields: Vec<String>,
    /// Sample points found inside their object (no rays cast for them).
    pub inside_points: u64,
}

/// Which objects get a field (see the module docs).
pub fn objects_needing_fields(scene: &Scene) -> Vec<bool> {
    let movable: Vec<bool> = scene.objects.iter().map(|o| o.motion == Motion::Movable).collect();
    (0..movable.len())
        .map(|x| {
            (0..movable.len()).any(|y| y != x && (movable[x] || movable[y]))
                && FlatOutline::of(&scene.objects[x].mesh).is_none()
        })
        .collect()
}

/// The direction set of `params` (from `cache_dir` when given) and its tree.
pub fn directions(
    params: &PrecomputeParams,
    cache_dir: Option<&Path>,
) -> Result<(DirectionSet, Vec<f64>, DirectionTree), PrecomputeError> {
    let rp =
        RepulsionParams { seed: params.direction_seed, wedges: params.turn_steps.max(1), ..RepulsionParams::default() };
    let n = params.directions as usize;
    let set = match cache_dir {
        Some(dir) => DirectionSet::load_or_generate(dir, n, &rp, |_, _| {}).map(|r| r.0),
        None => DirectionSet::generate(n, &rp, |_, _| {}),
    }?;
    let areas = set.cell_areas();
    let tree = vcut_data::direction_tree(set.directions(), &areas, params)?;
    Ok((set, areas, tree))
}

fn encode_all(
    cuts: &[vcut_cut::Cut],
    format: ValueFormat,
    coding: ShapeCoding,
    id: SectionId,
) -> Result<Vec<Vec<u8>>, PrecomputeError> {
    cuts.iter()
        .map(|c| coding.encode(c, format))
        .collect::<Result<_, _>>()
        .map_err(|error| PrecomputeError::Encode { section: id.to_string(), error })
}

/// Raw occlusion rays/s, measured on samples of a stage's own rays (collected first, then cast
/// on their own, on all cores), interleaved with the stage section by section so both figures
/// see the same machine conditions.
#[derive(Debug, Default)]
struct RawMeter {
    rays: u64,
    seconds: f64,
}

impl RawMeter {
    /// Casts `rays` against `occ` and adds them and the time taken.
    fn measure(&mut self, occ: &Occluder, rays: &[(Vec3, Vec3)]) {
        let start = Instant::now();
        let hits: usize =
            rays.par_chunks(256).map(|c| c.iter().filter(|&&(o, d)| occ.occluded(o, d, f32::INFINITY)).count()).sum();
        std::hint::black_box(hits);
        self.seconds += start.elapsed().as_secs_f64();
        self.rays += rays.len() as u64;
    }

    /// Measures the rays of every sample point, in batches of about 256k rays (bounded memory).
    fn measure_all(&mut self, occ: &Occluder, points: impl Iterator<Item = Vec<(Vec3, Vec3)>>) {
        let mut batch = Vec::new();
        for rays in points {
            batch.extend(rays);
            if batch.len() >= 1 << 18 {
                self.measure(occ, &batch);
                batch.clear();
            }
        }
        self.measure(occ, &batch);
    }

    fn rate(&self) -> f64 {
        if self.seconds > 0.0 { self.rays as f64 / self.seconds } else { 0.0 }
    }
}

/// Every `RAW_STRIDE`-th vertex or sample point of a section has its rays re-cast raw.
const RAW_STRIDE: usize = 61;

/// The rays an SVC vertex casts (origin, direction), in the stage's order.
fn svc_rays(tree: &DirectionTree, origin: Vec3, normal: Vec3) -> Vec<(Vec3, Vec3)> {
    let mut rays = Vec::new();
    let mut out = vec![0.0f32; tree.leaf_count()];
    visit_leaves(
        tree,
        |cone| cone_outside(cone, normal, crate::Angle::RIGHT).then_some(0.0),
        |d| {
            if normal.dot(d) > 0.0 {
                rays.push((origin, d));
            }
            0.0
        },
        &mut out,
    );
    rays
}

/// The rays a field sample point casts (inside the object's bounding cone).
fn field_rays(tree: &DirectionTree, p: Vec3, l: &FieldLayout) -> Vec<(Vec3, Vec3)> {
    let mut rays = Vec::new();
    let mut out = vec![0.0f32; tree.leaf_count()];
    let bound = crate::field::BoundingCone::from_point(p, l.center, l.radius);
    visit_leaves(
        tree,
        |cone| bound.is_some_and(|b| b.excludes(cone)).then_some(1.0),
        |dir| {
            if !bound.is_some_and(|b| b.misses(dir)) {
                rays.push((p, dir));
            }
            1.0
        },
        &mut out,
    );
    rays
}

/// Runs the precompute (resuming `<output>.partial` if present). Setting `interrupt` stops it
/// after the section being computed; the finished sections stay for the next run.
pub fn precompute(job: &Job<'_>, progress: &dyn Progress, interrupt: &AtomicBool) -> Result<Summary, PrecomputeError> {
    precompute_with(job, None, progress, interrupt)
}

/// [`precompute`], reusing the directions, layouts and occluders an estimate built
/// ([`crate::estimate::estimate`]) when given.
pub fn precompute_with<'a>(
    job: &'a Job<'a>,
    setup: Option<Setup<'a>>,
    progress: &dyn Progress,
    interrupt: &AtomicBool,
) -> Result<Summary, PrecomputeError> {
    run_sections(job, setup, None, progress, interrupt)
}

/// [`precompute_with`] for shard `index` of `plan` ([`crate::plan::plan`]): writes the shard file
/// `job.output` — the header sections, the `shard` section, then only the cut sections the plan
/// gives this shard ([`vcut_data::shard`]). Resumes and stops as a whole run does.
pub fn precompute_shard<'a>(
    job: &'a Job<'a>,
    setup: Option<Setup<'a>>,
    index: u32,
    plan: &ShardPlan,
    progress: &dyn Progress,
    interrupt: &AtomicBool,
) -> Result<Summary, PrecomputeError> {
    run_sections(job, setup, Some((index, plan)), progress, interrupt)
}

fn run_sections<'a>(
    job: &'a Job<'a>,
    setup: Option<Setup<'a>>,
    shard: Option<(u32, &ShardPlan)>,
    progress: &dyn Progress,
    interrupt: &AtomicBool,
) -> Result<Summary, PrecomputeError> {
    let p = &job.params;
    p.check()?;
    let scene = job.scene;
    if scene.objects.is_empty() {
        return Err(PrecomputeError::Scene { scene: job.scene_source.clone(), reason: "has no objects".into() });
    }
    let mut writer = Writer::open(&job.output)?;
    let mut stages = Vec::new();
    let check_interrupt = |w: &Writer| -> Result<(), PrecomputeError> {
        if interrupt.load(Ordering::Relaxed) {
            return Err(PrecomputeError::Interrupted {
                partial: vcut_data::file::partial_path(&job.output),
                sections: w.written(),
            });
        }
        Ok(())
    };

    // Stage 1: parameters, directions and tree, meshes, field layouts.
    let t0 = Instant::now();
    progress.stage("directions", 1);
    let record =
        vcut_data::Record { scene: job.scene_source.clone(), environment: job.environment.clone(), params: p.clone() };
    let params_text = record.text(concat!("vcut-precompute ", env!("CARGO_PKG_VERSION")));
    writer.put(SectionId::params(), params_text.as_bytes())?;
    let setup = match setup {
        Some(s) => s,
        None => Setup::new(job)?,
    };
    let tree = &setup.tree;
    writer.put(
        SectionId::directions(),
        &sections::encode_directions(setup.set.directions(), &setup.areas, tree.leaf_to_input()),
    )?;
    for (i, o) in scene.objects.iter().enumerate() {
        writer.put(SectionId::mesh(i as u32), &sections::encode_mesh(&o.name, o.motion, &o.material, &o.mesh))?;
        if let Some(surface) = vcut_data::surface::encode(&o.mesh, &o.textures) {
            writer.put(SectionId::surface(i as u32), &surface)?;
        }
    }
    for (i, l) in setup.layouts.iter().enumerate() {
        if let Some(l) = l {
            writer.put(SectionId::field_layout(i as u32), &sections::encode_field_layout(l))?;
        }
    }
    // What a renderer needs besides the objects, so the file renders without its scene file.
    for (id, bytes) in vcut_data::view::scene_sections(scene) {
        writer.put(id, &bytes)?;
    }
    let sections = crate::plan::cut_sections(scene, p, &setup.layouts);
    let mut owned: Option<HashSet<SectionId>> = None;
    if let Some((index, plan)) = shard {
        if !plan.sections().iter().map(|s| s.id).eq(sections.iter().map(|s| s.id)) {
            return Err(PrecomputeError::Plan(format!(
                "its {} sections are not the {} of scene {} with these parameters",
                plan.sections().len(),
                sections.len(),
                job.scene_source
            )));
        }
        let bytes = plan.encode(index).map_err(|e| PrecomputeError::Plan(e.to_string()))?;
        writer.put(SectionId::shard(), &bytes)?;
        owned = Some(plan.sections().iter().filter(|s| s.owner == index).map(|s| s.id).collect());
    }
    let mine = |kind: SectionKind| -> Vec<CutSection> {
        sections
            .iter()
            .filter(|s| s.id.kind == kind && owned.as_ref().is_none_or(|o| o.contains(&s.id)))
            .copied()
            .collect()
    };
    progress.advance(1);
    progress.end_stage();
    stages.push(StageSummary { seconds: t0.elapsed().as_secs_f64(), ..StageSummary::new("directions") });
    let root = tree.height();

    // Stage 2: SVCs.
    let t0 = Instant::now();
    let svc_sections = mine(SectionKind::Svc);
    let mut raw = RawMeter::default();
    progress.stage("svc", svc_sections.iter().map(|s| s.units).sum());
    let mut svc = StageSummary::new("svc");
    for &CutSection { id, units, .. } in &svc_sections {
        let i = id.a as usize;
        let start = id.b as usize * p.svc_chunk as usize;
        let end = start + units as usize;
        check_interrupt(&writer)?;
        if svc.try_keep(&mut writer, id, (end - start) as u64, progress)? {
            continue;
        }
        let c0 = Instant::now();
        let results: Vec<(vcut_cut::Cut, RayStats)> = (start..end)
            .into_par_iter()
            .map_init(
                || setup.scratch(),
                |scratch, v| {
                    let out = setup.svc_cut(i, v, scratch);
                    progress.advance(1);
                    out
                },
            )
            .collect();
        let (cuts, stats): (Vec<vcut_cut::Cut>, Vec<RayStats>) = results.into_iter().unzip();
        svc.rays = stats.into_iter().fold(svc.rays, |a, b| a + b);
        let encoded = encode_all(&cuts, p.svc_values, p.shape_coding, id)?;
        writer.put(id, &sections::encode_cut_array(root, p.svc_values, p.shape_coding, &encoded, None))?;
        svc.compute_seconds += c0.elapsed().as_secs_f64();
        svc.computed += 1;
        progress.section(id, false);
        raw.measure_all(
            setup.svc_occluder(i),
            (start..end).step_by(RAW_STRIDE).map(|v| {
                let (origin, normal) = setup.svc_origin(i, v);
                svc_rays(tree, origin, normal)
            }),
        );
    }
    progress.end_stage();
    svc.raw_rays_per_second = raw.rate();
    svc.seconds = t0.elapsed().as_secs_f64();
    stages.push(svc);

    // Stage 3: fields.
    let t0 = Instant::now();
    let field_objects = setup.field_objects();
    let mut raw = RawMeter::default();
    let field_sections = mine(SectionKind::Field);
    progress.stage("fields", field_sections.iter().map(|s| s.units).sum());
    let mut fields = StageSummary::new("fields");
    let mut inside_points = 0u64;
    for &CutSection { id, .. } in &field_sections {
        let (i, s) = (id.a as usize, id.b);
        let l = setup.layouts[i].unwrap_or_else(|| unreachable!("a field section of an object without a field"));
        check_interrupt(&writer)?;
        if fields.try_keep(&mut writer, id, l.points_per_sphere() as u64, progress)? {
            continue;
        }
        let c0 = Instant::now();
        let sc = sphere_cuts(setup.alone(i), tree, &setup.leaf_areas, &l, s, p.field_select());
        progress.advance(l.points_per_sphere() as u64);
        inside_points += sc.inside.iter().filter(|&&x| x).count() as u64;
        fields.rays += sc.stats;
        let encoded = encode_all(&sc.cuts, p.field_values, p.shape_coding, id)?;
        writer
            .put(id, &sections::encode_cut_array(root, p.field_values, p.shape_coding, &encoded, Some(&sc.inside)))?;
        fields.compute_seconds += c0.elapsed().as_secs_f64();
        fields.computed += 1;
        progress.section(id, false);
        raw.measure_all(
            setup.alone(i),
            (0..l.points_per_sphere())
                .step_by(RAW_STRIDE)
                .filter(|&k| !sc.inside[k])
                .map(|k| field_rays(tree, l.point(s, k as u32), &l)),
        );
    }
    progress.end_stage();
    fields.raw_rays_per_second = raw.rate();
    fields.seconds = t0.elapsed().as_secs_f64();
    stages.push(fields);

    let file_bytes = writer.finish()?;
    let sizes = cut_sizes(&job.output)?;
    Ok(Summary {
        stages,
        sizes,
        file_bytes,
        fields: field_objects.iter().map(|&i| scene.objects[i].name.clone()).collect(),
        inside_points,
    })
}

/// Reads every cut section of a `.vcuts` file and totals its sizes per kind: as stored, in the
/// paper's height codec, and in the node-index baseline (u16/u32 index + f32 value).
pub fn cut_sizes(path: &Path) -> Result<Vec<CutSizes>, FileError> {
    let mut r = Reader::open(path)?;
    let mut out =
        vec![CutSizes { kind: "svc", ..CutSizes::default() }, CutSizes { kind: "field", ..CutSizes::default() }];
    let ids: Vec<SectionId> = r.entries().iter().map(|e| e.id).collect();
    for id in ids {
        let k = match id.kind {
            SectionKind::Svc => 0,
            SectionKind::Field => 1,
            _ => continue,
        };
        let bytes = r.section(id)?;
        let payload_len = bytes.len() as u64;
        let a = sections::CutArray::parse(bytes).map_err(|e| r.section_error(id, e))?;
        let s = &mut out[k];
        s.sections += 1;
        s.bytes += payload_len;
        // Same container (header, offsets, lengths), then per cut its own coding.
        let fixed = a.overhead() as u64;
        s.index_baseline_bytes += fixed;
        s.heights_codec_bytes += fixed;
        for c in 0..a.len() {
            let n = a.node_count(c).map_err(|e| r.section_error(id, e))? as u64;
            s.cuts += 1;
            s.nodes += n;
            s.max_nodes = s.max_nodes.max(n);
            s.index_baseline_bytes += codec::index_coded_size(n as usize, a.root_height()) as u64;
            s.heights_codec_bytes += codec::height_coded_size(n as usize, a.root_height(), a.format()) as u64;
        }
    }
    Ok(out)
}
