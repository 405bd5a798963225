//! Codec round trips over random valid cuts from 2 to 65,536 leaves: f32 is bit-exact, the
//! quantised formats stay within their documented bound, the index baseline is exact, and the
//! sizes are what `height_coded_size` / `index_coded_size` say.

use proptest::prelude::*;
use vcut_cut::Cut;
use vcut_cut::codec::{self, ValueFormat};

/// A random valid cut (depth-first splits) with values in [0, 1] — 0 and 1 included.
fn cut_strategy() -> impl Strategy<Value = Cut> {
    (1u32..=16, any::<u64>(), 0.2f64..0.97).prop_map(|(root, seed, split)| {
        let mut state = seed;
        let mut rnd = move || {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut heights = Vec::new();
        let mut stack = vec![root];
        while let Some(h) = stack.pop() {
            if h > 0 && rnd() < split {
                stack.extend([h - 1, h - 1]);
            } else {
                heights.push(h as u8);
            }
        }
        let values = heights
            .iter()
            .map(|_| match rnd() {
                r if r < 0.1 => 0.0,
                r if r < 0.2 => 1.0,
                _ => rnd() as f32,
            })
            .collect();
        Cut::new(root, heights, values).unwrap()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn height_codec_round_trips(cut in cut_strategy()) {
        for format in ValueFormat::ALL {
            let bytes = codec::encode_heights(&cut, format).unwrap();
            prop_assert_eq!(bytes.len(), codec::height_coded_size(cut.len(), cut.root_height(), format));
            let back = codec::decode_heights(&bytes, cut.root_height(), format).unwrap();
            prop_assert_eq!(back.heights(), cut.heights());
            for (a, b) in back.values().iter().zip(cut.values()) {
                if format == ValueFormat::F32 {
                    prop_assert_eq!(a.to_bits(), b.to_bits());
                } else {
                    prop_assert!((a - b).abs() <= format.max_error(), "{}: {} vs {}", format.name(), a, b);
                }
            }
            // 0 and 1 survive every format exactly (all-occluded and all-visible stay exact).
            for (a, b) in back.values().iter().zip(cut.values()) {
                if *b == 0.0 || *b == 1.0 {
                    prop_assert_eq!(a, b);
                }
            }
        }
    }

    #[test]
    fn split_flags_round_trip_and_never_exceed_the_height_codec(cut in cut_strategy()) {
        for format in ValueFormat::ALL {
            let bytes = codec::encode_split_flags(&cut, format).unwrap();
            prop_assert_eq!(bytes.len(), codec::split_flags_size(&cut, format));
            prop_assert!(bytes.len() <= codec::height_coded_size(cut.len(), cut.root_height(), format));
            let back = codec::decode_split_flags(&bytes, cut.root_height(), format).unwrap();
            prop_assert_eq!(back.heights(), cut.heights());
            if format == ValueFormat::F32 {
                prop_assert_eq!(&back, &cut);
            }
        }
        // Binary values (an exact field): one bit each, exact, in both shape codings.
        let mut binary = cut.clone();
        for v in binary.values_mut() {
            *v = if *v > 0.5 { 1.0 } else { 0.0 };
        }
        let bytes = codec::encode_split_flags(&binary, ValueFormat::U1).unwrap();
        prop_assert_eq!(codec::decode_split_flags(&bytes, cut.root_height(), ValueFormat::U1).unwrap(), binary.clone());
        let bytes = codec::encode_heights(&binary, ValueFormat::U1).unwrap();
        prop_assert_eq!(bytes.len(), codec::height_coded_size(cut.len(), cut.root_height(), ValueFormat::U1));
        prop_assert_eq!(codec::decode_heights(&bytes, cut.root_height(), ValueFormat::U1).unwrap(), binary);
    }

    #[test]
    fn index_baseline_round_trips(cut in cut_strategy()) {
        let bytes = codec::encode_indices(&cut);
        prop_assert_eq!(bytes.len(), codec::index_coded_size(cut.len(), cut.root_height()));
        prop_assert_eq!(codec::decode_indices(&bytes, cut.root_height()).unwrap(), cut);
    }

    #[test]
    fn decoding_arbitrary_bytes_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..64), root in 0u32..=17) {
        for format in ValueFormat::WITH_BINARY {
            if let Ok(c) = codec::decode_heights(&bytes, root, format) {
                prop_assert!(c.validate().is_ok());
            }
            if let Ok(c) = codec::decode_split_flags(&bytes, root, format) {
                prop_assert!(c.validate().is_ok());
                // Canonical: what decodes re-encodes to the same bytes (f32 and u1 are exact).
                if matches!(format, ValueFormat::F32 | ValueFormat::U1) {
                    prop_assert_eq!(codec::encode_split_flags(&c, format).unwrap(), bytes.clone());
                }
            }
        }
        if let Ok(c) = codec::decode_indices(&bytes, root) {
            prop_assert!(c.validate().is_ok());
        }
    }
}

#[test]
fn height_coding_is_smaller_than_indices() {
    // 4-bit heights + u8 values against u16 indices + f32 values: 1.5 vs 6 bytes per node.
    let n = 1000;
    let h = codec::height_coded_size(n, 15, ValueFormat::U8) as f64;
    let i = codec::index_coded_size(n, 15) as f64;
    assert!(h / i < 0.26, "{}", h / i);
}
