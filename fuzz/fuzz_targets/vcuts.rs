//! Fuzz target: a `.vcuts` file of arbitrary bytes — the container (header, offset table,
//! section checksums), every section payload parser behind it (the view's TOML and the embedded
//! map included) and a shard file's plan — gives errors, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::io::Cursor;
use std::path::Path;
use vcut_data::file::{Reader, SectionKind};
use vcut_data::sections;
use vcut_data::shard::ShardPlan;

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else { return };
    match mode % 9 {
        // Payload parsers directly, so the fuzzer need not forge CRCs to reach them.
        0 => {
            if let Ok(a) = sections::CutArray::parse(rest.to_vec()) {
                for i in 0..a.len().min(64) {
                    if let Ok(c) = a.cut(i) {
                        assert!(c.validate().is_ok());
                    }
                    let _ = (a.node_count(i), a.inside(i));
                }
            }
        }
        1 => {
            let _ = sections::decode_mesh(rest);
        }
        2 => {
            let _ = sections::decode_directions(rest);
        }
        3 => {
            let _ = sections::decode_field_layout(rest);
        }
        5 => {
            if let Ok((index, plan)) = ShardPlan::decode(rest) {
                assert!(index < plan.shards() && plan.sections().iter().all(|s| s.owner < plan.shards()));
            }
        }
        6 => {
            if let Ok(text) = std::str::from_utf8(rest) {
                let _ = vcut_data::View::parse(text);
            }
        }
        7 => {
            if let Ok(map) = vcut_envmap::embed::decode(rest, "fuzz") {
                assert_eq!(
                    vcut_envmap::embed::decode(&vcut_envmap::embed::encode(&map), "fuzz").unwrap().texels(),
                    map.texels()
                );
            }
        }
        8 => {
            // A surface payload read against the vertex count it claims, so the parse goes on.
            let claimed = rest.get(..4).map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
            let _ = vcut_data::surface::decode(rest, claimed);
        }
        // The container: open, then read every section it lists and parse the cut arrays.
        _ => {
            if let Ok(mut r) = Reader::from_source(Cursor::new(rest), Path::new("fuzz.vcuts")) {
                let ids: Vec<_> = r.entries().iter().map(|e| e.id).collect();
                for id in ids {
                    if let Ok(bytes) = r.section(id)
                        && matches!(id.kind, SectionKind::Svc | SectionKind::Field)
                        && let Ok(a) = sections::CutArray::parse(bytes)
                    {
                        for i in 0..a.len().min(16) {
                            let _ = a.cut(i);
                        }
                    }
                }
            }
        }
    }
});
