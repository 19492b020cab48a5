//! Mutations of valid files into malformed ones: byte-level damage for every format (truncation,
//! bit flips, inserted, deleted and duplicated bytes, lying integers) and token-level damage for
//! text formats (numbers swapped for NaN, huge or negative values, closing tags and brackets
//! removed, lines duplicated, dropped or swapped, names exchanged).

use super::rng::Pcg32;
use std::ops::Range;

/// Numbers a reader must survive where a count, index, size or coordinate is expected.
const WEIRD_NUMBERS: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e999",
    "-1e999",
    "-1",
    "-0",
    "0",
    "1e-45",
    "3.4e38",
    "1e308",
    "2147483647",
    "2147483648",
    "4294967295",
    "4294967296",
    "-2147483649",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999",
    "65536",
    "1.5",
    "0x10",
    "1,2",
    "",
];

/// Fragments that break the syntax of XML, JSON, TOML, OBJ, MTL and PLY headers.
const WEIRD_TOKENS: &[&str] = &[
    "<",
    ">",
    "</",
    "/>",
    "<!--",
    "&",
    "&amp;",
    "&#0;",
    "&#xFFFFFF;",
    "\"",
    "'",
    "=",
    "{",
    "}",
    "[",
    "]",
    "[[",
    ",",
    ":",
    "$",
    "$x",
    "\\",
    "\0",
    "\u{e9}",
    "\u{FFFD}",
    "\n",
    "\r",
    "\t",
    "#",
    "-",
    "/",
    "//",
    "..",
    "../",
    " ",
    "f",
    "v",
    "end_header",
    "element",
    "property",
    "list",
    "true",
    "null",
];

/// Integers written over binary data: sizes and counts that lie.
const WEIRD_INTS: &[u64] = &[
    0,
    1,
    0x7f,
    0x80,
    0xff,
    0x7fff,
    0xffff,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x1_0000_0000,
    u64::MAX,
    i64::MAX as u64,
];

/// Makes one malformed input from `seed`; `others` are the target's other seeds (for splicing).
/// Applies one to three mutations, text ones only if `text`.
pub fn mutate(rng: &mut Pcg32, seed: &[u8], others: &[Vec<u8>], text: bool) -> Vec<u8> {
    let mut data = seed.to_vec();
    let count = 1 + rng.below(3);
    for _ in 0..count {
        let kinds = if text { 16 } else { 9 };
        match rng.below(kinds) {
            0 => truncate(rng, &mut data),
            1 => flip_bits(rng, &mut data),
            2 => set_byte(rng, &mut data),
            3 => insert_bytes(rng, &mut data),
            4 => delete_range(rng, &mut data),
            5 => duplicate_chunk(rng, &mut data),
            6 => write_int(rng, &mut data),
            7 => splice(rng, &mut data, others),
            8 => repeat_chunk(rng, &mut data),
            9 | 10 => replace_number(rng, &mut data),
            11 => delete_closer(rng, &mut data),
            12 => line_edit(rng, &mut data),
            13 => swap_words(rng, &mut data),
            14 => insert_token(rng, &mut data),
            _ => replace_number(rng, &mut data),
        }
    }
    data
}

/// `seed` cut after every `step`-th byte: the files a crash or a full disk leaves behind.
pub fn truncations(seed: &[u8], max: usize) -> Vec<Vec<u8>> {
    let step = seed.len().div_ceil(max).max(1);
    (0..seed.len())
        .step_by(step)
        .map(|n| seed[..n].to_vec())
        .collect()
}

fn random_range(rng: &mut Pcg32, len: usize, max_len: usize) -> Range<usize> {
    if len == 0 {
        return 0..0;
    }
    let start = rng.below(len);
    let n = 1 + rng.below(max_len.max(1).min(len - start));
    start..start + n
}

fn truncate(rng: &mut Pcg32, data: &mut Vec<u8>) {
    if !data.is_empty() {
        let at = rng.below(data.len());
        data.truncate(at);
    }
}

fn flip_bits(rng: &mut Pcg32, data: &mut [u8]) {
    if data.is_empty() {
        return;
    }
    for _ in 0..1 + rng.below(8) {
        let i = rng.below(data.len());
        data[i] ^= 1 << rng.below(8);
    }
}

fn set_byte(rng: &mut Pcg32, data: &mut [u8]) {
    if !data.is_empty() {
        let i = rng.below(data.len());
        data[i] = *rng.pick(&[0, 0xff, 0x7f, 0x80, b'\n', b' ', b'-', b'9', b'"', b'<']);
    }
}

fn insert_bytes(rng: &mut Pcg32, data: &mut Vec<u8>) {
    let at = rng.below(data.len() + 1);
    let n = 1 + rng.below(16);
    let bytes: Vec<u8> = if rng.chance(2) {
        vec![rng.next_u32() as u8; n]
    } else {
        (0..n).map(|_| rng.next_u32() as u8).collect()
    };
    data.splice(at..at, bytes);
}

fn delete_range(rng: &mut Pcg32, data: &mut Vec<u8>) {
    let r = random_range(rng, data.len(), (data.len() / 8).max(1));
    data.drain(r);
}

fn duplicate_chunk(rng: &mut Pcg32, data: &mut Vec<u8>) {
    let r = random_range(rng, data.len(), 64);
    let chunk = data[r].to_vec();
    let at = rng.below(data.len() + 1);
    data.splice(at..at, chunk);
}

fn repeat_chunk(rng: &mut Pcg32, data: &mut Vec<u8>) {
    let r = random_range(rng, data.len(), 32);
    let chunk = data[r.clone()].to_vec();
    let times = 1 + rng.below(64);
    let copies: Vec<u8> = chunk
        .iter()
        .copied()
        .cycle()
        .take(chunk.len() * times)
        .collect();
    data.splice(r.end..r.end, copies);
}

fn write_int(rng: &mut Pcg32, data: &mut [u8]) {
    let width = *rng.pick(&[1usize, 2, 4, 8]);
    if data.len() < width {
        return;
    }
    let mut v = *rng.pick(WEIRD_INTS);
    if rng.chance(4) {
        v = v.wrapping_add(rng.below(3) as u64).wrapping_sub(1);
    }
    let bytes = if rng.chance(2) {
        v.to_le_bytes()
    } else {
        v.to_be_bytes()
    };
    let at = rng.below(data.len() - width + 1);
    let src = if bytes[0] == 0 && width < 8 && rng.chance(2) {
        &bytes[8 - width..]
    } else {
        &bytes[..width]
    };
    data[at..at + width].copy_from_slice(src);
}

fn splice(rng: &mut Pcg32, data: &mut Vec<u8>, others: &[Vec<u8>]) {
    if others.is_empty() {
        return;
    }
    let other = rng.pick(others);
    let cut = rng.below(data.len() + 1);
    let from = rng.below(other.len() + 1);
    data.truncate(cut);
    data.extend_from_slice(&other[from..]);
}

/// Where the numbers are: an optional sign, digits, and the digits, dots and exponents after them.
fn numbers(data: &[u8]) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < data.len() {
        let start = i;
        if (data[i] == b'-' || data[i] == b'+') && data.get(i + 1).is_some_and(u8::is_ascii_digit) {
            i += 1;
        }
        if data[i].is_ascii_digit() && (start == 0 || !data[start - 1].is_ascii_alphanumeric()) {
            while i < data.len()
                && (data[i].is_ascii_digit()
                    || data[i] == b'.'
                    || ((data[i] == b'e' || data[i] == b'E')
                        && data
                            .get(i + 1)
                            .is_some_and(|c| c.is_ascii_digit() || *c == b'-')))
            {
                i += if data[i] == b'e' || data[i] == b'E' {
                    2
                } else {
                    1
                };
            }
            out.push(start..i.min(data.len()));
        } else {
            i = start + 1;
        }
    }
    out
}

fn replace_number(rng: &mut Pcg32, data: &mut Vec<u8>) {
    let found = numbers(data);
    if found.is_empty() {
        return insert_token(rng, data);
    }
    let r = rng.pick(&found).clone();
    let with = rng.pick(WEIRD_NUMBERS).as_bytes().to_vec();
    data.splice(r, with);
}

/// Removes a closing tag, bracket, brace or quote, or (a quarter of the time) everything from one
/// to the end.
fn delete_closer(rng: &mut Pcg32, data: &mut Vec<u8>) {
    let closers: Vec<usize> = data
        .iter()
        .enumerate()
        .filter(|(i, &c)| {
            matches!(c, b'}' | b']' | b'"' | b'>' | b')')
                || (c == b'<' && data.get(i + 1) == Some(&b'/'))
        })
        .map(|(i, _)| i)
        .collect();
    if closers.is_empty() {
        return delete_range(rng, data);
    }
    let at = *rng.pick(&closers);
    if rng.chance(4) {
        data.truncate(at);
        return;
    }
    let end = if data[at] == b'<' {
        data[at..]
            .iter()
            .position(|&c| c == b'>')
            .map_or(data.len(), |p| at + p + 1)
    } else {
        at + 1
    };
    data.drain(at..end);
}

fn line_ranges(data: &[u8]) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut start = 0;
    for (i, &c) in data.iter().enumerate() {
        if c == b'\n' {
            out.push(start..i + 1);
            start = i + 1;
        }
    }
    if start < data.len() {
        out.push(start..data.len());
    }
    out
}

fn line_edit(rng: &mut Pcg32, data: &mut Vec<u8>) {
    let lines = line_ranges(data);
    if lines.len() < 2 {
        return delete_range(rng, data);
    }
    let a = rng.pick(&lines).clone();
    match rng.below(3) {
        0 => {
            let copy = data[a.clone()].to_vec();
            let times = if rng.chance(4) { 1 + rng.below(100) } else { 1 };
            let at = rng.pick(&lines).start;
            for _ in 0..times {
                data.splice(at..at, copy.iter().copied());
            }
        }
        1 => {
            data.drain(a);
        }
        _ => {
            let b = rng.pick(&lines).clone();
            let (first, second) = if a.start <= b.start { (a, b) } else { (b, a) };
            if first.end <= second.start {
                let mut out = data[..first.start].to_vec();
                out.extend_from_slice(&data[second.clone()]);
                out.extend_from_slice(&data[first.end..second.start]);
                out.extend_from_slice(&data[first.clone()]);
                out.extend_from_slice(&data[second.end..]);
                *data = out;
            }
        }
    }
}

fn words(data: &[u8]) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < data.len() {
        if data[i].is_ascii_alphabetic() || data[i] == b'_' {
            let start = i;
            while i < data.len() && (data[i].is_ascii_alphanumeric() || data[i] == b'_') {
                i += 1;
            }
            out.push(start..i);
        } else {
            i += 1;
        }
    }
    out
}

/// Puts one name where another was: a material name where a shape type is expected, an attribute
/// name as a value, a keyword out of place.
fn swap_words(rng: &mut Pcg32, data: &mut Vec<u8>) {
    let found = words(data);
    if found.len() < 2 {
        return insert_token(rng, data);
    }
    let to = rng.pick(&found).clone();
    let from = rng.pick(&found).clone();
    let word = data[from].to_vec();
    data.splice(to, word);
}

fn insert_token(rng: &mut Pcg32, data: &mut Vec<u8>) {
    let at = rng.below(data.len() + 1);
    let token = rng.pick(WEIRD_TOKENS).as_bytes().to_vec();
    data.splice(at..at, token);
}
