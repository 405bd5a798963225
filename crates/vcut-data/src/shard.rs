//! Sharded precompute: a [`ShardPlan`] assigns the cut sections of a `.vcuts` file (SVC chunks,
//! field spheres) to N shards; each shard writes a **shard file** — the whole file's header
//! sections (params, directions, meshes, field layouts), a `shard` section holding its index and
//! the plan, then the cut sections it owns, in the file's order — and [`gather`] joins the N
//! shard files into the file one machine would have written, byte for byte.
//!
//! **Why byte-identical.** A container file's bytes depend only on the sequence of sections put
//! into its writer (ids and payloads, in order); every section is a deterministic function of the
//! scene and the parameters. Gather puts the header sections, then every planned section in the
//! plan's order (the one-machine run's order) with the payload its owner computed: the same
//! sequence, hence the same bytes.
//!
//! **The plan** is longest-processing-time-first: sections by falling cost (ties: file order),
//! each to the shard with the least cost so far (ties: the lowest index). It depends only on the
//! costs, so every shard computes the same plan on its own, and each shard file records it: gather
//! checks the shards agree, names the sections of any shard that is missing and the shard that
//! owes them, and refuses shard files of different runs.
//!
//! **The `shard` payload**: `index u32, shards u32, sections u32`, then per section `kind u32,
//! a u32, b u32, owner u32, units u64, cost u64`; little-endian.

use crate::file::{FileError, Kind, Reader, SectionId, SectionKind, Sections, Writer};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// One cut section of a plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlannedSection {
    /// The section.
    pub id: SectionId,
    /// Vertices (SVC chunk) or sample points (field sphere) it covers.
    pub units: u64,
    /// Estimated cost (rays, in whatever unit the planner uses; only ratios matter).
    pub cost: u64,
    /// The shard that computes it.
    pub owner: u32,
}

/// The cut sections of a file, each assigned to one of `shards` shards.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShardPlan {
    shards: u32,
    sections: Vec<PlannedSection>,
}

/// Why a plan cannot be made or read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PlanError {
    /// Zero shards asked for.
    #[error("a plan needs at least one shard")]
    NoShards,
    /// A shard index beyond the count.
    #[error("shard index {index} is not below the shard count {shards} (indices are 0-based)")]
    Index {
        /// The index.
        index: u32,
        /// The count.
        shards: u32,
    },
    /// A malformed `shard` payload.
    #[error("{0}")]
    Payload(String),
}

impl ShardPlan {
    /// Assigns `sections` (id, units, cost), given in file order, to `shards` shards by longest
    /// processing time first (see the module docs).
    pub fn balance(sections: &[(SectionId, u64, u64)], shards: u32) -> Result<ShardPlan, PlanError> {
        if shards == 0 {
            return Err(PlanError::NoShards);
        }
        let mut order: Vec<usize> = (0..sections.len()).collect();
        order.sort_by(|&x, &y| sections[y].2.cmp(&sections[x].2).then(x.cmp(&y)));
        let mut load = vec![0u64; shards as usize];
        let mut owner = vec![0u32; sections.len()];
        for k in order {
            let s = (0..shards as usize).min_by_key(|&s| (load[s], s)).unwrap_or(0);
            load[s] += sections[k].2;
            owner[k] = s as u32;
        }
        let sections = sections
            .iter()
            .zip(owner)
            .map(|(&(id, units, cost), owner)| PlannedSection { id, units, cost, owner })
            .collect();
        Ok(ShardPlan { shards, sections })
    }

    /// Shards.
    pub fn shards(&self) -> u32 {
        self.shards
    }

    /// The sections in file order.
    pub fn sections(&self) -> &[PlannedSection] {
        &self.sections
    }

    /// Whether shard `index` computes `id`.
    pub fn owns(&self, index: u32, id: SectionId) -> bool {
        self.sections.iter().any(|s| s.id == id && s.owner == index)
    }

    /// The summed cost of each shard.
    pub fn loads(&self) -> Vec<u64> {
        let mut load = vec![0u64; self.shards as usize];
        for s in &self.sections {
            load[s.owner as usize] += s.cost;
        }
        load
    }

    /// The largest shard's cost over the mean shard's (1 is perfect balance; 0 for no work).
    pub fn balance_ratio(&self) -> f64 {
        let load = self.loads();
        let total: u64 = load.iter().sum();
        if total == 0 {
            return 0.0;
        }
        *load.iter().max().unwrap_or(&0) as f64 / (total as f64 / self.shards as f64)
    }

    /// The `shard` section of shard `index`.
    pub fn encode(&self, index: u32) -> Result<Vec<u8>, PlanError> {
        if index >= self.shards {
            return Err(PlanError::Index { index, shards: self.shards });
        }
        let mut out = Vec::with_capacity(12 + 32 * self.sections.len());
        for x in [index, self.shards, self.sections.len() as u32] {
            out.extend_from_slice(&x.to_le_bytes());
        }
        for s in &self.sections {
            for x in [s.id.kind as u32, s.id.a, s.id.b, s.owner] {
                out.extend_from_slice(&x.to_le_bytes());
            }
            out.extend_from_slice(&s.units.to_le_bytes());
            out.extend_from_slice(&s.cost.to_le_bytes());
        }
        Ok(out)
    }

    /// Reads a `shard` section: the shard's index and the plan.
    pub fn decode(bytes: &[u8]) -> Result<(u32, ShardPlan), PlanError> {
        let bad = |m: String| PlanError::Payload(m);
        let u32_at = |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
        let u64_at = |at: usize| u64::from(u32_at(at)) | (u64::from(u32_at(at + 4)) << 32);
        if bytes.len() < 12 {
            return Err(bad(format!("{} bytes, shorter than the 12-byte head", bytes.len())));
        }
        let (index, shards, count) = (u32_at(0), u32_at(4), u32_at(8) as usize);
        if count.checked_mul(32).and_then(|n| n.checked_add(12)) != Some(bytes.len()) {
            return Err(bad(format!("{count} sections need {} bytes, got {}", 12 + 32 * count as u64, bytes.len())));
        }
        if shards == 0 {
            return Err(PlanError::NoShards);
        }
        if index >= shards {
            return Err(PlanError::Index { index, shards });
        }
        let mut sections = Vec::with_capacity(count);
        for k in 0..count {
            let at = 12 + 32 * k;
            let kind = match SectionKind::from_code(u32_at(at)) {
                Some(kind @ (SectionKind::Svc | SectionKind::Field)) => kind,
                _ => return Err(bad(format!("section {k}: kind {} is not a cut section", u32_at(at)))),
            };
            let owner = u32_at(at + 12);
            if owner >= shards {
                return Err(PlanError::Index { index: owner, shards });
            }
            let id = SectionId::new(kind, u32_at(at + 4), u32_at(at + 8));
            sections.push(PlannedSection { id, owner, units: u64_at(at + 16), cost: u64_at(at + 24) });
        }
        Ok((index, ShardPlan { shards, sections }))
    }
}

/// The shard file of shard `index` of `shards` for the output `path`:
/// `dir/x.vcuts` → `dir/x.shard-2-of-4.vcuts`.
pub fn shard_path(path: &Path, index: u32, shards: u32) -> PathBuf {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!("{stem}.shard-{index}-of-{shards}.vcuts"))
}

/// The shard a finished file is, if it is one: its index and plan (errors name the file).
pub fn read_shard(reader: &mut Reader) -> Result<Option<(u32, ShardPlan)>, FileError> {
    let id = SectionId::shard();
    if !reader.has(id) {
        return Ok(None);
    }
    let bytes = reader.section(id)?;
    ShardPlan::decode(&bytes).map(Some).map_err(|e| reader.section_error(id, e))
}

/// Why shard files could not be gathered. Every variant names the files it is about.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GatherError {
    /// A shard file could not be read, or the output not written.
    #[error(transparent)]
    File(#[from] FileError),
    /// No shard files were given.
    #[error("no shard files to gather")]
    Empty,
    /// A file that is not a shard of a sharded precompute.
    #[error("{}: not a shard file (it has no shard section); gather takes the files `precompute --shard` wrote", path.display())]
    NotAShard {
        /// The file.
        path: PathBuf,
    },
    /// Two files of the same shard.
    #[error("shard {index} of {shards} given twice: {} and {}", first.display(), second.display())]
    Duplicate {
        /// The shard.
        index: u32,
        /// Shards in the plan.
        shards: u32,
        /// The first file.
        first: PathBuf,
        /// The second.
        second: PathBuf,
    },
    /// Shard files of different runs (scene, parameters or plan differ).
    #[error(
        "{}: {what} differs from that of {} — the shards come from different runs (scene, parameters or shard count)",
        path.display(),
        first.display()
    )]
    Mismatch {
        /// The file that differs.
        path: PathBuf,
        /// The first shard file given.
        first: PathBuf,
        /// What differs (a section, or "the plan").
        what: String,
    },
    /// Shards are missing (or miss sections they owe).
    #[error("incomplete: {}", describe_missing(missing, *shards))]
    Incomplete {
        /// Shards in the plan.
        shards: u32,
        /// Per shard that owes sections, the sections missing.
        missing: Vec<(u32, Vec<String>)>,
    },
}

fn describe_missing(missing: &[(u32, Vec<String>)], shards: u32) -> String {
    let parts: Vec<String> = missing
        .iter()
        .map(|(i, s)| {
            let shown: Vec<&str> = s.iter().take(4).map(String::as_str).collect();
            let more =
                if s.len() > shown.len() { format!(", … {} more", s.len() - shown.len()) } else { String::new() };
            format!("shard {i} of {shards} owes {} sections ({}{more})", s.len(), shown.join(", "))
        })
        .collect();
    let rerun: Vec<String> = missing.iter().map(|(i, _)| i.to_string()).collect();
    format!("{}; run these shards again: {}", parts.join("; "), rerun.join(","))
}

impl GatherError {
    /// The shards to run again, when that is what the error asks for.
    pub fn shards_to_rerun(&self) -> Vec<u32> {
        match self {
            GatherError::Incomplete { missing, .. } => missing.iter().map(|(i, _)| *i).collect(),
            _ => Vec::new(),
        }
    }
}

/// What [`gather`] did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Gathered {
    /// Shards joined.
    pub shards: u32,
    /// Sections written (header and cut sections).
    pub sections: usize,
    /// Bytes of the output.
    pub bytes: u64,
}

/// Which shards of `shards` a set of finished shard files holds, checking they belong to one
/// run: for a farm that wants to know what to run again without gathering.
pub fn missing_shards(files: &[PathBuf]) -> Result<(u32, Vec<u32>), GatherError> {
    let set = ShardSet::open(files)?;
    let shards = set.plan.shards;
    Ok((shards, (0..shards).filter(|i| !set.by_index.contains_key(i)).collect()))
}

/// The shard files of one run, opened and checked against each other.
struct ShardSet {
    readers: Vec<Reader>,
    plan: ShardPlan,
    by_index: HashMap<u32, usize>,
    /// The header section ids (every shard's are the same), in file order.
    header: Vec<SectionId>,
}

impl ShardSet {
    fn open(files: &[PathBuf]) -> Result<ShardSet, GatherError> {
        let mut readers = Vec::new();
        let mut plan: Option<ShardPlan> = None;
        let mut by_index: HashMap<u32, usize> = HashMap::new();
        for path in files {
            let mut r = Reader::open(path)?;
            let (index, p) = read_shard(&mut r)?.ok_or_else(|| GatherError::NotAShard { path: path.clone() })?;
            match &plan {
                None => plan = Some(p),
                Some(first) if *first != p => {
                    return Err(GatherError::Mismatch {
                        path: path.clone(),
                        first: files[0].clone(),
                        what: "the plan".into(),
                    });
                }
                Some(_) => {}
            }
            if let Some(&k) = by_index.get(&index) {
                return Err(GatherError::Duplicate {
                    index,
                    shards: plan.as_ref().map_or(0, |p| p.shards),
                    first: files[k].clone(),
                    second: path.clone(),
                });
            }
            by_index.insert(index, readers.len());
            readers.push(r);
        }
        let plan = plan.ok_or(GatherError::Empty)?;
        let is_header = |id: &SectionId| !matches!(id.kind, SectionKind::Svc | SectionKind::Field | SectionKind::Shard);
        let header: Vec<SectionId> = readers[0].entries().iter().map(|e| e.id).filter(is_header).collect();
        let head_of = |r: &Reader| -> Vec<(SectionId, u32, u64)> {
            r.entries().iter().filter(|e| is_header(&e.id)).map(|e| (e.id, e.crc, e.len)).collect()
        };
        let first = head_of(&readers[0]);
        for (k, r) in readers.iter().enumerate().skip(1) {
            let other = head_of(r);
            if other != first {
                let what = first
                    .iter()
                    .zip(&other)
                    .find(|(a, b)| a != b)
                    .map(|(a, _)| format!("section {}", a.0))
                    .unwrap_or_else(|| format!("the header's section count ({} against {})", other.len(), first.len()));
                return Err(GatherError::Mismatch { path: files[k].clone(), first: files[0].clone(), what });
            }
        }
        Ok(ShardSet { readers, plan, by_index, header })
    }
}

/// Joins the shard files of one sharded run into `output` (written under `<output>.partial`,
/// renamed when complete): checks that they come from one run, that no shard is given twice,
/// that every planned section is there (naming the missing ones and the shard that owes them),
/// and every section's checksum as it is copied. The result is byte-identical to the file one
/// machine writes.
pub fn gather(files: &[PathBuf], output: &Path) -> Result<Gathered, GatherError> {
    let mut set = ShardSet::open(files)?;
    let mut missing: std::collections::BTreeMap<u32, Vec<String>> = Default::default();
    for s in &set.plan.sections {
        if !set.by_index.get(&s.owner).is_some_and(|&k| set.readers[k].has(s.id)) {
            missing.entry(s.owner).or_default().push(s.id.to_string());
        }
    }
    if !missing.is_empty() {
        return Err(GatherError::Incomplete { shards: set.plan.shards, missing: missing.into_iter().collect() });
    }
    let mut writer = Writer::open(output)?;
    for &id in &set.header {
        let bytes = set.readers[0].section(id)?;
        writer.put(id, &bytes)?;
    }
    for s in &set.plan.sections {
        let k = set.by_index[&s.owner];
        let bytes = set.readers[k].section(s.id)?;
        writer.put(s.id, &bytes)?;
    }
    let sections = writer.written();
    let bytes = writer.finish()?;
    Ok(Gathered { shards: set.plan.shards, sections, bytes })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn svc(a: u32, b: u32) -> SectionId {
        SectionId::svc(a, b)
    }

    #[test]
    fn longest_first_balances_and_ties_go_to_file_order() {
        let sections = [(svc(0, 0), 10, 5), (svc(0, 1), 10, 5), (svc(0, 2), 10, 9), (svc(0, 3), 10, 1)];
        let plan = ShardPlan::balance(&sections, 2).unwrap();
        let owners: Vec<u32> = plan.sections().iter().map(|s| s.owner).collect();
        // 9 → shard 0; 5 (chunk 0) → shard 1; 5 (chunk 1) → shard 1 (5 < 9); 1 → shard 0.
        assert_eq!(owners, [1, 1, 0, 0]);
        assert_eq!(plan.loads(), [10, 10]);
        assert_eq!(plan.balance_ratio(), 1.0);
        assert!(plan.owns(0, svc(0, 2)) && !plan.owns(1, svc(0, 2)));
        assert_eq!(ShardPlan::balance(&sections, 0), Err(PlanError::NoShards));
    }

    #[test]
    fn the_shard_section_round_trips_and_rejects_damage() {
        let sections = [(svc(0, 0), 10, 5), (SectionId::field(1, 3), 600, 70)];
        let plan = ShardPlan::balance(&sections, 3).unwrap();
        let bytes = plan.encode(2).unwrap();
        assert_eq!(ShardPlan::decode(&bytes).unwrap(), (2, plan.clone()));
        assert_eq!(plan.encode(3), Err(PlanError::Index { index: 3, shards: 3 }));
        assert!(matches!(ShardPlan::decode(&bytes[..bytes.len() - 1]), Err(PlanError::Payload(_))));
        let mut bad = bytes.clone();
        bad[12..16].copy_from_slice(&(SectionKind::Mesh as u32).to_le_bytes());
        assert!(matches!(ShardPlan::decode(&bad), Err(PlanError::Payload(m)) if m.contains("not a cut section")));
        let mut bad = bytes;
        bad[0..4].copy_from_slice(&7u32.to_le_bytes());
        assert_eq!(ShardPlan::decode(&bad), Err(PlanError::Index { index: 7, shards: 3 }));
    }

    #[test]
    fn shard_files_are_named_beside_the_output() {
        assert_eq!(shard_path(Path::new("out/teapot.vcuts"), 2, 4), Path::new("out/teapot.shard-2-of-4.vcuts"));
    }
}
