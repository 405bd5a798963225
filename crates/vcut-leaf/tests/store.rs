//! `.vleaf` files: what is saved loads back bit for bit equal to what was computed in memory; a
//! matching file is reused and another's inputs are named; a run killed after some checkpoints
//! resumes from them to the same bytes; damage is named and the data computed again.

use std::path::{Path, PathBuf};
use vcut_leaf::lvc::{Lvc, LvcParams};
use vcut_leaf::material::LeafMaterial;
use vcut_leaf::plant::{PlantParams, plant};
use vcut_leaf::prt::{PrtParams, Transfer};
use vcut_leaf::scene::LeafScene;
use vcut_leaf::shade::LeafData;
use vcut_leaf::store::{Inputs, LeafSection, Reuse, StoreError, open, precompute};

fn scene() -> LeafScene {
    // 30 leaves of 153 vertices: 4,590 vertices, three LVC checkpoints and two transfer sections.
    let params = PlantParams { leaves: 30, ..PlantParams::default() };
    plant(&params, &LeafMaterial::default()).unwrap()
}

const LVC: LvcParams =
    LvcParams { resolution: 4, sun_diameter_deg: 0.53, disk_samples: 16, content: vcut_leaf::lvc::Content::Visibility };
const PRT: PrtParams = PrtParams { rays: 16, bounces: 1, seed: 3 };

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("vcut-leaf-store-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d.join("plant.vleaf")
}

fn quiet(_: &str, _: usize, _: usize) {}

/// Every map decoded, and the transfer's floats: equal bit for bit.
fn assert_same(a: &LeafData, b: &LeafData, n: usize) {
    assert_eq!(a.lvc.compressed_bytes(), b.lvc.compressed_bytes());
    let (mut x, mut y) = (vec![0u8; n], vec![0u8; n]);
    for j in 0..a.lvc.directions().len() {
        assert_eq!(a.lvc.has(j), b.lvc.has(j));
        if a.lvc.has(j) {
            a.lvc.decode(j, &mut x).unwrap();
            b.lvc.decode(j, &mut y).unwrap();
            assert_eq!(x, y, "sun direction {j}");
        }
    }
    let bits = |t: &Transfer| -> Vec<u32> {
        let d = t.direct.iter().flatten().flatten().map(|f| f.to_bits());
        let i = t.indirect.iter().flatten().flatten().flat_map(|v| v.to_array()).map(f32::to_bits);
        d.chain(i).collect()
    };
    assert_eq!(bits(&a.transfer), bits(&b.transfer));
    assert_eq!(a.transfer.rays_traced, b.transfer.rays_traced);
}

#[test]
fn saved_data_loads_back_as_computed_and_is_reused_only_for_its_inputs() {
    let scene = scene();
    let n = scene.vertex_count();
    assert!(n > 2 * vcut_leaf::lvc::CHUNK, "{n} vertices: several checkpoints");
    let path = scratch("reuse");
    let inputs = Inputs { scene: &scene, lvc: LVC, prt: PRT, suns: None };
    let (saved, first) = precompute(&inputs, &path, Reuse::IfMatching, &quiet).unwrap();
    assert!(!first.loaded && first.file_bytes > 0 && first.replaced.is_none());
    assert!(!vcut_container::partial_path(&path).exists());
    let memory =
        LeafData::new(Lvc::compute(&scene, &LVC, |_, _| {}), Transfer::compute(&scene, &PRT, |_, _| {})).unwrap();
    assert_same(&saved, &memory, n);
    // The same inputs load the file; what is read is what was computed.
    let (loaded, again) = precompute(&inputs, &path, Reuse::IfMatching, &quiet).unwrap();
    assert!(again.loaded);
    assert_same(&loaded, &memory, n);
    // Other inputs are named, and computed again over the file.
    let other = Inputs { prt: PrtParams { rays: 25, ..PRT }, ..inputs };
    let e = open(&path, &other).err().unwrap().to_string();
    assert!(e.contains("plant.vleaf") && e.contains("prt_rays = 16") && e.contains("prt_rays = 25"), "{e}");
    let (_, redone) = precompute(&other, &path, Reuse::IfMatching, &quiet).unwrap();
    assert!(!redone.loaded && redone.replaced.unwrap().contains("prt_rays"));
    // Only some sun directions.
    let suns = [3usize, 40];
    let few = Inputs { suns: Some(&suns), ..inputs };
    let (part, _) = precompute(&few, &path, Reuse::Never, &quiet).unwrap();
    assert!(part.lvc.has(3) && part.lvc.has(40) && !part.lvc.has(4));
    assert_same(&open(&path, &few).unwrap(), &part, n);
}

#[test]
fn a_killed_run_resumes_its_checkpoints_to_the_same_bytes() {
    let scene = scene();
    let path = scratch("resume");
    let inputs = Inputs { scene: &scene, lvc: LVC, prt: PRT, suns: None };
    let (whole_data, _) = precompute(&inputs, &path, Reuse::Never, &quiet).unwrap();
    let whole = std::fs::read(&path).unwrap();
    // A run killed after its params and two LVC checkpoints: copy those sections into a
    // partial file as that run left it.
    let partial = vcut_container::partial_path(&path);
    let mut r = vcut_container::Reader::<LeafSection>::open(&path).unwrap();
    let ids: Vec<_> = r.entries().iter().map(|e| e.id).collect();
    let mut w = vcut_container::Writer::<LeafSection>::open(&path).unwrap();
    for id in &ids[..3] {
        w.put(*id, &r.section(*id).unwrap()).unwrap();
    }
    drop(w);
    std::fs::remove_file(&path).unwrap();
    assert!(partial.exists());
    let (resumed, outcome) = precompute(&inputs, &path, Reuse::IfMatching, &quiet).unwrap();
    assert_eq!(outcome.lvc_chunks_resumed, 2);
    assert_eq!(std::fs::read(&path).unwrap(), whole, "resumed bytes differ");
    assert_same(&resumed, &whole_data, scene.vertex_count());
}

#[test]
fn damage_is_named_and_computed_again() {
    let scene = scene();
    let path = scratch("damage");
    let inputs = Inputs { scene: &scene, lvc: LVC, prt: PRT, suns: None };
    precompute(&inputs, &path, Reuse::Never, &quiet).unwrap();
    let good = std::fs::read(&path).unwrap();
    let r = vcut_container::Reader::<LeafSection>::open(&path).unwrap();
    let e = *r.entries().iter().find(|e| e.id.kind == LeafSection::Transfer).unwrap();
    drop(r);
    let mut bad = good.clone();
    bad[e.offset as usize + 5] ^= 0x40;
    std::fs::write(&path, &bad).unwrap();
    let err = open(&path, &inputs).err().unwrap();
    assert!(matches!(err, StoreError::File(_)), "{err}");
    assert!(err.to_string().contains("transfer (vertex chunk 0): checksum mismatch"), "{err}");
    let (_, outcome) = precompute(&inputs, &path, Reuse::IfMatching, &quiet).unwrap();
    assert!(outcome.replaced.unwrap().contains("checksum mismatch"));
    assert_eq!(std::fs::read(&path).unwrap(), good);
    // Not a .vleaf at all.
    let not = Path::new(&path).with_extension("txt");
    std::fs::write(&not, b"hello").unwrap();
    let e = open(&not, &inputs).err().unwrap().to_string();
    assert!(e.contains("plant.txt") && e.contains("not a usable .vleaf file"), "{e}");
}
