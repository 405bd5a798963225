//! Fuzz target: decoding arbitrary bytes as a cut (height codec and split-flag coding in every
//! value format, and the index baseline) gives an error or a valid cut, never a panic; exact
//! formats re-encode to the same bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vcut_cut::codec::{self, ValueFormat};

fuzz_target!(|data: &[u8]| {
    let Some((&root, rest)) = data.split_first() else { return };
    let root = u32::from(root % 20);
    for format in ValueFormat::WITH_BINARY {
        let exact = matches!(format, ValueFormat::F32 | ValueFormat::U1);
        if let Ok((cut, used)) = codec::decode_heights_prefix(rest, root, format) {
            assert!(cut.validate().is_ok() && used <= rest.len());
            // What decodes re-encodes to the same bytes in exact formats (others round).
            if exact {
                assert_eq!(codec::encode_heights(&cut, format).ok().as_deref(), Some(&rest[..used]));
            }
        }
        if let Ok((cut, used)) = codec::decode_split_flags_prefix(rest, root, format) {
            assert!(cut.validate().is_ok() && used <= rest.len());
            if exact {
                assert_eq!(codec::encode_split_flags(&cut, format).ok().as_deref(), Some(&rest[..used]));
            }
        }
    }
    if let Ok((cut, _)) = codec::decode_indices_prefix(rest, root) {
        assert!(cut.validate().is_ok());
    }
});
