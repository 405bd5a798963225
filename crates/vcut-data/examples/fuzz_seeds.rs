//! Writes the `vcuts` fuzz target's seeds from a `.vcuts` file: `file.seed` (mode byte 4, the
//! whole container) and `section-K.seed` (mode byte + payload, K the section kind) for the first
//! directions, mesh, field layout, SVC, field and view sections; and, when the file embeds no map
//! (its scene's is built in), `section-9.seed` from a 16×8 studio map.
//!
//! Regenerate after a format change:
//! `cargo xtask precompute --scene fuzz/seeds/vcuts-src/tiny.toml --preset fast --directions 64
//!  --field-spheres 2 --field-resolution 1 -o target/tiny.vcuts --fresh`, then
//! `cargo run -p vcut-data --example fuzz_seeds -- target/tiny.vcuts fuzz/seeds/vcuts`.

use std::path::Path;
use vcut_data::file::{Reader, SectionKind};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [file, out] = args.as_slice() else { return Err("usage: fuzz_seeds FILE.vcuts OUTDIR".into()) };
    let out = Path::new(out);
    let bytes = std::fs::read(file)?;
    std::fs::write(out.join("file.seed"), [&[4u8][..], &bytes].concat())?;
    let mut reader = Reader::open(Path::new(file))?;
    let ids: Vec<_> = reader.entries().iter().map(|e| e.id).collect();
    let mut seen = Vec::new();
    for id in ids {
        // The fuzz target's mode byte for each payload parser.
        let mode = match id.kind {
            SectionKind::Directions => 2u8,
            SectionKind::Mesh => 1,
            SectionKind::FieldLayout => 3,
            SectionKind::Svc | SectionKind::Field => 0,
            SectionKind::Shard => 5,
            SectionKind::View => 6,
            SectionKind::Environment => 7,
            SectionKind::Surface => 8,
            SectionKind::Params => continue,
        };
        if seen.contains(&id.kind) {
            continue;
        }
        seen.push(id.kind);
        let payload = reader.section(id)?;
        std::fs::write(out.join(format!("section-{}.seed", id.kind as u32)), [&[mode][..], &payload].concat())?;
    }
    if !seen.contains(&SectionKind::Environment) {
        let map = vcut_envmap::procedural::Studio::default().bake(16);
        let seed = [&[7u8][..], &vcut_envmap::embed::encode(&map)].concat();
        std::fs::write(out.join(format!("section-{}.seed", SectionKind::Environment as u32)), seed)?;
    }
    Ok(())
}
