//! Run-length encoding of byte maps, lossless, in the PackBits family with one addition for LVC
//! maps, whose bytes are mostly 0 (in shadow) and 255 (lit): a run of either of those two costs a
//! single byte. A control byte `c` and its six low bits `n = c & 63`:
//!
//! | `c` | meaning |
//! |---|---|
//! | `0x00–0x3F` | n + 1 zeros (1–64) |
//! | `0x40–0x7F` | n + 1 bytes 255 (1–64) |
//! | `0x80–0xBF` | n + 1 literal bytes follow (1–64) |
//! | `0xC0–0xFF` | the next byte, repeated n + 3 times (3–66) |
//!
//! A map of alternating shadow and light costs one byte per run: the ratio is the mean run length.
//! A zero or 255 alone (or two) inside a literal span stays in it (a control of its own would
//! split the span and cost as much again).

/// Why a byte stream does not decode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RleError {
    /// The stream ended inside a control's bytes.
    #[error("run-length data truncated at byte {at}")]
    Truncated {
        /// Offset of the control whose bytes are missing.
        at: usize,
    },
    /// The stream decodes to a different length than expected.
    #[error("run-length data decodes to {got} bytes, expected {expected}")]
    Length {
        /// Bytes the stream holds (at least; decoding stops at the first byte too many).
        got: usize,
        /// Bytes expected.
        expected: usize,
    },
    /// An encoder state ([`Encoder::state`]) that no encoder can be in.
    #[error("malformed run-length encoder state ({len} bytes)")]
    State {
        /// Its length.
        len: usize,
    },
}

const SPAN: usize = 64;
const MIN_RUN: usize = 3;
const MAX_RUN: usize = 66;

/// An encoder fed one byte at a time (so a map can be encoded while it is computed).
#[derive(Debug, Clone, Default)]
pub struct Encoder {
    out: Vec<u8>,
    literal: Vec<u8>,
    run_byte: u8,
    run_len: usize,
}

impl Encoder {
    /// An empty encoder.
    pub fn new() -> Encoder {
        Encoder::default()
    }

    fn flush_literal(&mut self) {
        for chunk in self.literal.chunks(SPAN) {
            self.out.push(0x80 | (chunk.len() - 1) as u8);
            self.out.extend_from_slice(chunk);
        }
        self.literal.clear();
    }

    fn flush_run(&mut self) {
        let (b, mut n) = (self.run_byte, self.run_len);
        self.run_len = 0;
        if (b == 0 || b == 255) && (n >= MIN_RUN || self.literal.is_empty()) {
            self.flush_literal();
            let base = if b == 0 { 0x00 } else { 0x40 };
            while n > 0 {
                let k = n.min(SPAN);
                self.out.push(base | (k - 1) as u8);
                n -= k;
            }
        } else if n >= MIN_RUN {
            self.flush_literal();
            self.out.push(0xC0 | (n - MIN_RUN) as u8);
            self.out.push(b);
        } else {
            self.literal.extend(std::iter::repeat_n(b, n));
            if self.literal.len() >= SPAN {
                let full = self.literal.len() / SPAN * SPAN;
                let rest = self.literal.split_off(full);
                self.flush_literal();
                self.literal = rest;
            }
        }
    }

    /// Appends one byte.
    #[inline]
    pub fn push(&mut self, b: u8) {
        let cap = if b == 0 || b == 255 { SPAN } else { MAX_RUN };
        if self.run_len > 0 && b == self.run_byte && self.run_len < cap {
            self.run_len += 1;
            return;
        }
        if self.run_len > 0 {
            self.flush_run();
        }
        self.run_byte = b;
        self.run_len = 1;
    }

    /// Takes the bytes encoded so far; the stream goes on after them (a checkpoint stores
    /// these and [`Encoder::state`]).
    pub fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.out)
    }

    /// What was pushed but is not encoded yet: `[run byte, run length, literal span…]`, at most
    /// 65 bytes. [`Encoder::from_state`] continues from it exactly as this encoder would.
    pub fn state(&self) -> Vec<u8> {
        let mut s = Vec::with_capacity(2 + self.literal.len());
        s.push(self.run_byte);
        s.push(self.run_len as u8);
        s.extend_from_slice(&self.literal);
        s
    }

    /// An encoder (with no output taken yet) in `state`, as [`Encoder::state`] wrote it; a state
    /// no encoder can be in is an error.
    pub fn from_state(state: &[u8]) -> Result<Encoder, RleError> {
        let bad = RleError::State { len: state.len() };
        let [run_byte, run_len, literal @ ..] = state else { return Err(bad) };
        let cap = if *run_byte == 0 || *run_byte == 255 { SPAN } else { MAX_RUN };
        if usize::from(*run_len) > cap || literal.len() >= SPAN {
            return Err(bad);
        }
        Ok(Encoder { out: Vec::new(), literal: literal.to_vec(), run_byte: *run_byte, run_len: usize::from(*run_len) })
    }

    /// The encoded stream.
    pub fn finish(mut self) -> Vec<u8> {
        if self.run_len > 0 {
            self.flush_run();
        }
        self.flush_literal();
        self.out
    }
}

/// Encodes `bytes`.
pub fn encode(bytes: &[u8]) -> Vec<u8> {
    let mut e = Encoder::new();
    for &b in bytes {
        e.push(b);
    }
    e.finish()
}

/// Decodes `data` into `out`, which it must fill exactly.
pub fn decode(data: &[u8], out: &mut [u8]) -> Result<(), RleError> {
    let (mut i, mut o) = (0usize, 0usize);
    let expected = out.len();
    while i < data.len() {
        let c = data[i];
        let n = usize::from(c & 63);
        let (len, used) = match c >> 6 {
            0 | 1 => (n + 1, 1),
            2 => (n + 1, 1 + n + 1),
            _ => (n + MIN_RUN, 2),
        };
        if i + used > data.len() {
            return Err(RleError::Truncated { at: i });
        }
        let dst = out.get_mut(o..o + len).ok_or(RleError::Length { got: o + len, expected })?;
        match c >> 6 {
            0 => dst.fill(0),
            1 => dst.fill(255),
            2 => dst.copy_from_slice(&data[i + 1..i + used]),
            _ => dst.fill(data[i + 1]),
        }
        i += used;
        o += len;
    }
    if o != expected {
        return Err(RleError::Length { got: o, expected });
    }
    Ok(())
}

/// Decodes a stream a span at a time, in order: what [`decode`] writes, without the whole map
/// in memory (a reader of many maps at once keeps one cursor per map).
#[derive(Debug, Clone)]
pub struct Cursor<'a> {
    data: &'a [u8],
    /// Next control byte.
    at: usize,
    /// The control being emitted, and how many of its bytes are left.
    control: usize,
    left: usize,
}

impl<'a> Cursor<'a> {
    /// A cursor at the start of `data`.
    pub fn new(data: &'a [u8]) -> Cursor<'a> {
        Cursor { data, at: 0, control: 0, left: 0 }
    }

    /// Fills `out` with the next `out.len()` decoded bytes.
    pub fn next_into(&mut self, out: &mut [u8]) -> Result<(), RleError> {
        let mut o = 0;
        while o < out.len() {
            if self.left == 0 {
                let i = self.at;
                let c = *self.data.get(i).ok_or(RleError::Length { got: o, expected: out.len() })?;
                let n = usize::from(c & 63);
                let (len, used) = match c >> 6 {
                    0 | 1 => (n + 1, 1),
                    2 => (n + 1, 1 + n + 1),
                    _ => (n + MIN_RUN, 2),
                };
                if i + used > self.data.len() {
                    return Err(RleError::Truncated { at: i });
                }
                (self.control, self.left, self.at) = (i, len, i + used);
            }
            let c = self.data[self.control];
            let take = self.left.min(out.len() - o);
            let dst = &mut out[o..o + take];
            match c >> 6 {
                0 => dst.fill(0),
                1 => dst.fill(255),
                2 => {
                    let from = self.control + 1 + (usize::from(c & 63) + 1 - self.left);
                    dst.copy_from_slice(&self.data[from..from + take]);
                }
                _ => dst.fill(self.data[self.control + 1]),
            }
            self.left -= take;
            o += take;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn decode_inverts_encode(bytes in proptest::collection::vec(prop_oneof![Just(0u8), Just(255u8), any::<u8>()], 0..2000)) {
            let e = encode(&bytes);
            let mut out = vec![0u8; bytes.len()];
            decode(&e, &mut out).unwrap();
            prop_assert_eq!(&out, &bytes);
            // A cursor gives the same bytes in spans of any length.
            let mut cursor = Cursor::new(&e);
            let mut spans = Vec::new();
            for (k, chunk) in bytes.chunks(37).enumerate() {
                let mut span = vec![0u8; chunk.len().min(1 + k % 37)];
                cursor.next_into(&mut span).unwrap();
                let mut rest = vec![0u8; chunk.len() - span.len()];
                cursor.next_into(&mut rest).unwrap();
                spans.extend(span);
                spans.extend(rest);
            }
            prop_assert_eq!(&spans, &bytes);
            prop_assert!(cursor.next_into(&mut [0u8]).is_err());
            // Never worse than one control byte per 64 literals.
            prop_assert!(e.len() <= bytes.len() + bytes.len().div_ceil(64));
        }

        #[test]
        fn a_stream_checkpointed_anywhere_continues_to_the_same_bytes(
            bytes in proptest::collection::vec(prop_oneof![Just(0u8), Just(255u8), Just(9u8), any::<u8>()], 0..600),
            cuts in proptest::collection::vec(0usize..600, 0..6),
        ) {
            let mut cuts: Vec<usize> = cuts.into_iter().filter(|&c| c <= bytes.len()).collect();
            cuts.sort_unstable();
            let mut e = Encoder::new();
            let (mut out, mut at) = (Vec::new(), 0);
            for c in cuts.into_iter().chain([bytes.len()]) {
                for &b in &bytes[at..c] {
                    e.push(b);
                }
                at = c;
                out.extend(e.take_output());
                e = Encoder::from_state(&e.state()).unwrap();
            }
            out.extend(e.finish());
            prop_assert_eq!(out, encode(&bytes));
        }

        #[test]
        fn encoder_states_from_garbage_are_refused_or_work(state in proptest::collection::vec(any::<u8>(), 0..80), tail in proptest::collection::vec(any::<u8>(), 0..100)) {
            if let Ok(mut e) = Encoder::from_state(&state) {
                for b in &tail {
                    e.push(*b);
                }
                let _ = e.finish();
            }
        }

        #[test]
        fn garbage_is_an_error_not_a_panic(data in proptest::collection::vec(any::<u8>(), 0..300), n in 0usize..600) {
            let mut out = vec![0u8; n];
            let _ = decode(&data, &mut out);
        }
    }

    #[test]
    fn shadow_and_light_cost_a_byte_per_run_and_damage_is_named() {
        // Alternating runs of 10: one byte each.
        let bytes: Vec<u8> = (0..10_000).map(|i| if (i / 10) % 2 == 0 { 0 } else { 255 }).collect();
        assert_eq!(encode(&bytes).len(), 1000);
        let mut bytes = vec![255u8; 10_000];
        bytes[5000..5100].fill(7);
        let e = encode(&bytes);
        assert!(e.len() < 200, "{}", e.len());
        let mut out = vec![0u8; 10_000];
        let mut cut = e.clone();
        cut.truncate(cut.iter().position(|&c| c >> 6 == 3).unwrap() + 1);
        assert!(matches!(decode(&cut, &mut out[..]), Err(RleError::Truncated { .. }) | Err(RleError::Length { .. })));
        assert_eq!(decode(&[0xC0], &mut out[..3]), Err(RleError::Truncated { at: 0 }));
        assert!(matches!(decode(&e, &mut out[..9_999]), Err(RleError::Length { .. })));
        let mut longer = vec![0u8; 10_001];
        assert_eq!(decode(&e, &mut longer), Err(RleError::Length { got: 10_000, expected: 10_001 }));
    }
}
