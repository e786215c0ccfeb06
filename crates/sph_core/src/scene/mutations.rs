//! Deterministic mutations of scene files, for fuzzing the loader: truncations, character
//! flips, numeric extremes, and deleted and duplicated keys.
//!
//! A scene file is user data, hot-reloaded while a person types: every mutation of a valid file
//! must load or be refused by [`crate::scene`], never panic and never allocate without
//! bound. The CI test (`tests/scene_fuzz.rs`) runs a few thousand of these; `sph-bench
//! fuzz-scenes --seed S --count N` runs as many as asked with the same generator.

use crate::rng::SplitMix64;
use crate::scene::{SceneError, SceneFile, SceneSetup};

/// Numbers that break naive arithmetic: infinities, NaN, the extremes of f32 and of the
/// integer types, negative zero, and values just past the loader's own bounds.
pub const EXTREMES: [&str; 16] = [
    "inf",
    "-inf",
    "NaN",
    "1e30",
    "-1e30",
    "-0",
    "0",
    "1e-30",
    "3.4e38",
    "1e300",
    "-1",
    "4294967295",
    "18446744073709551615",
    "-9223372036854775808",
    "1001",
    "1e19",
];

/// What a mutation did, for the report of a failing case.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Mutation {
    /// The text cut after this many bytes.
    Truncate(usize),
    /// The character at this byte replaced by another ASCII character.
    Flip(usize, char),
    /// The number at this byte replaced by one of [`EXTREMES`].
    Extreme(usize, &'static str),
    /// The line holding a key deleted.
    DeleteLine(usize),
    /// The line holding a key written twice.
    DuplicateLine(usize),
}

/// A mutated text and the mutations applied, in order.
#[derive(Clone, Debug)]
pub struct Mutant {
    /// The mutated scene file.
    pub text: String,
    /// What was done to it.
    pub mutations: Vec<Mutation>,
}

/// Mutant number `index` of `text` for `seed`: one to three mutations, the same every time.
pub fn mutant(text: &str, seed: u64, index: u64) -> Mutant {
    let mut rng = SplitMix64::new(seed ^ index.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    let count = 1 + rng.next_u64() % 3;
    let mut out = Mutant {
        text: text.to_owned(),
        mutations: Vec::new(),
    };
    for _ in 0..count {
        if let Some((text, mutation)) = mutate(&out.text, &mut rng) {
            out.text = text;
            out.mutations.push(mutation);
        }
    }
    out
}

fn pick(rng: &mut SplitMix64, n: usize) -> usize {
    (rng.next_u64() % n.max(1) as u64) as usize
}

/// One random mutation of `text`, or `None` when the text has nothing of the kind drawn.
fn mutate(text: &str, rng: &mut SplitMix64) -> Option<(String, Mutation)> {
    match rng.next_u64() % 5 {
        0 => {
            let at = floor_char_boundary(text, pick(rng, text.len()));
            Some((text[..at].to_owned(), Mutation::Truncate(at)))
        }
        1 => {
            let ascii: Vec<usize> = text
                .char_indices()
                .filter(|(_, c)| c.is_ascii())
                .map(|(i, _)| i)
                .collect();
            let at = *ascii.get(pick(rng, ascii.len()))?;
            // Printable ASCII, so the text stays UTF-8 as the loader requires.
            let c = char::from(b' ' + (rng.next_u64() % 95) as u8);
            let mut s = text.to_owned();
            s.replace_range(at..at + 1, c.encode_utf8(&mut [0; 4]));
            Some((s, Mutation::Flip(at, c)))
        }
        2 => {
            let numbers = number_spans(text);
            let (start, end) = *numbers.get(pick(rng, numbers.len()))?;
            let extreme = EXTREMES[pick(rng, EXTREMES.len())];
            let mut s = text.to_owned();
            s.replace_range(start..end, extreme);
            Some((s, Mutation::Extreme(start, extreme)))
        }
        kind => {
            let keyed: Vec<usize> = text
                .lines()
                .enumerate()
                .filter(|(_, l)| l.contains(':'))
                .map(|(k, _)| k)
                .collect();
            let line = *keyed.get(pick(rng, keyed.len()))?;
            let mut lines: Vec<&str> = text.lines().collect();
            let mutation = if kind == 3 {
                lines.remove(line);
                Mutation::DeleteLine(line + 1)
            } else {
                lines.insert(line, lines[line]);
                Mutation::DuplicateLine(line + 1)
            };
            Some((lines.join("\n"), mutation))
        }
    }
}

fn floor_char_boundary(text: &str, mut at: usize) -> usize {
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

/// The byte ranges of the numeric literals in `text` (digits with an optional sign, point and
/// exponent), outside comments.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if b == b'/' && bytes.get(i + 1) == Some(&b'/') {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        let starts_word = i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        if starts_word
            && (b.is_ascii_digit()
                || (b == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit)))
        {
            let start = i;
            i += 1;
            while i < bytes.len()
                && (bytes[i].is_ascii_digit()
                    || matches!(bytes[i], b'.' | b'e' | b'E' | b'_')
                    || (matches!(bytes[i], b'-' | b'+') && matches!(bytes[i - 1], b'e' | b'E')))
            {
                i += 1;
            }
            spans.push((start, i));
            continue;
        }
        i += 1;
    }
    spans
}

/// Parses and builds `text` as the loaders do (the Bevy asset loader, `sandbox --scene`,
/// `sph-bench --scene`): the scene, or the error naming the line and the field.
pub fn load(text: &str, file: &str) -> Result<SceneSetup, SceneError> {
    SceneFile::parse(text, file).and_then(|scene| scene.build(file, text))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_found_outside_comments_and_words() {
        let text = "// 12 in a comment\n(a: -1.5e-3, b2: 7, c: [3, 4_000])";
        let found: Vec<&str> = number_spans(text)
            .into_iter()
            .map(|(s, e)| &text[s..e])
            .collect();
        assert_eq!(found, ["-1.5e-3", "7", "3", "4_000"]);
    }

    #[test]
    fn mutants_are_deterministic_and_differ_from_the_source() {
        let text = "(\n  spacing: 0.02,\n  total: 300,\n)";
        let a = mutant(text, 7, 3);
        let b = mutant(text, 7, 3);
        assert_eq!(a.text, b.text);
        assert_eq!(a.mutations, b.mutations);
        let changed = (0..50).filter(|&k| mutant(text, 7, k).text != text).count();
        assert!(changed > 40, "{changed} of 50 mutants changed the text");
    }
}
