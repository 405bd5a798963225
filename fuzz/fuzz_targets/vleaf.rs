//! Fuzz target: `.vleaf` files must load or give an error, never panic. The first byte picks
//! the mode: 0 — the rest is a whole file (header, table, checksums); otherwise the rest is a
//! list of length-prefixed section payloads that this target wraps in a well-formed container
//! with the right `params` section for a small fixed plant, so the fuzzer reaches the LVC
//! checkpoint and transfer parsers behind the checksums.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;
use vcut_container::{SectionId, Writer};
use vcut_leaf::lvc::{Content, LvcParams};
use vcut_leaf::material::LeafMaterial;
use vcut_leaf::plant::{PlantParams, plant};
use vcut_leaf::prt::PrtParams;
use vcut_leaf::scene::LeafScene;
use vcut_leaf::store::LeafSections;
use vcut_leaf::store::{Inputs, LeafSection, open};

fn scene() -> &'static LeafScene {
    static SCENE: OnceLock<LeafScene> = OnceLock::new();
    SCENE.get_or_init(|| plant(&PlantParams { leaves: 2, ..PlantParams::default() }, &LeafMaterial::default()).unwrap())
}

fn inputs() -> Inputs<'static> {
    Inputs {
        scene: scene(),
        lvc: LvcParams { resolution: 2, sun_diameter_deg: 0.53, disk_samples: 4, content: Content::Visibility },
        prt: PrtParams { rays: 4, bounces: 1, seed: 1 },
        suns: None,
    }
}

/// In memory where the system has a tmpfs (the writer syncs the file it finishes: slow on disk).
fn path() -> PathBuf {
    let shm = std::path::Path::new("/dev/shm");
    let dir = if shm.is_dir() { shm.to_path_buf() } else { std::env::temp_dir() };
    dir.join(format!("vcut-fuzz-vleaf-{}.vleaf", std::process::id()))
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else { return };
    let path = path();
    let inputs = inputs();
    if mode == 0 {
        if std::fs::write(&path, rest).is_err() {
            return;
        }
    } else {
        // Sections: params (the right one), then (kind byte, a byte, u16 length, payload)*.
        let Ok(mut w) = Writer::<LeafSection>::open(&path) else { return };
        let _ = w.put(SectionId::params(), inputs.identity().as_bytes());
        let mut at = 0;
        while at + 4 <= rest.len() {
            let kind = [LeafSection::Lvc, LeafSection::Transfer, LeafSection::Summary][rest[at] as usize % 3];
            let a = u32::from(rest[at + 1] % 4);
            let len = usize::from(u16::from_le_bytes([rest[at + 2], rest[at + 3]]));
            at += 4;
            let payload = &rest[at..(at + len).min(rest.len())];
            at += payload.len();
            if w.put(SectionId::new(kind, a, 0), payload).is_err() {
                return;
            }
        }
        if w.finish().is_err() {
            return;
        }
    }
    if let Ok(d) = open(&path, &inputs) {
        let n = scene().vertex_count();
        let mut map = vec![0u8; n];
        for j in 0..d.lvc.directions().len() {
            assert!(d.lvc.decode(j, &mut map).is_ok(), "a loaded map decodes");
        }
        assert_eq!(d.transfer.direct.len(), n);
    }
    let _ = std::fs::remove_file(&path);
});
