//! A TIFF image file directory, in the classic layout (32-bit offsets) or
//! BigTIFF's (64-bit offsets, for files past 4 GiB).

/// An entry's field type, count and bytes.
type Encoded = (u16, u64, Vec<u8>);

/// One entry's value.
pub enum Value {
    Shorts(Vec<u16>),
    Longs(Vec<u32>),
    /// Offsets: LONG in a classic TIFF, LONG8 in a BigTIFF.
    Offsets(Vec<u64>),
    Doubles(Vec<f64>),
    /// NUL-terminated on writing.
    Ascii(String),
}

impl Value {
    /// The field type, the count and the bytes of the value.
    fn encode(&self, big: bool) -> Encoded {
        match self {
            Value::Shorts(v) => (
                3,
                v.len() as u64,
                v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            ),
            Value::Longs(v) => (
                4,
                v.len() as u64,
                v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            ),
            Value::Offsets(v) if big => (
                16,
                v.len() as u64,
                v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            ),
            Value::Offsets(v) => (
                4,
                v.len() as u64,
                v.iter().flat_map(|&x| (x as u32).to_le_bytes()).collect(),
            ),
            Value::Doubles(v) => (
                12,
                v.len() as u64,
                v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            ),
            Value::Ascii(text) => {
                let mut bytes = text.as_bytes().to_vec();
                bytes.push(0);
                (2, bytes.len() as u64, bytes)
            }
        }
    }
}

/// The file's header: byte order, version and the first directory's offset
/// (patched in once the directory is written, at [`first_directory_at`]).
pub fn header(big: bool) -> Vec<u8> {
    match big {
        false => [b"II".as_slice(), &42u16.to_le_bytes(), &0u32.to_le_bytes()].concat(),
        true => [
            b"II".as_slice(),
            &43u16.to_le_bytes(),
            &8u16.to_le_bytes(),
            &0u16.to_le_bytes(),
            &0u64.to_le_bytes(),
        ]
        .concat(),
    }
}

/// Where the header holds the first directory's offset, and its width.
pub fn first_directory_at(big: bool) -> (u64, usize) {
    if big {
        (8, 8)
    } else {
        (4, 4)
    }
}

/// The directory of `entries` (sorted by tag here) to be written at byte
/// `at` of the file, its out-of-line values after it; `next` is the next
/// directory's offset (0: none).
pub fn encode(mut entries: Vec<(u16, Value)>, at: u64, big: bool, next: u64) -> Vec<u8> {
    entries.sort_by_key(|(tag, _)| *tag);
    let (count_bytes, entry_bytes, inline) = if big { (8, 20, 8) } else { (2, 12, 4) };
    let offset = |v: u64, out: &mut Vec<u8>| match big {
        true => out.extend_from_slice(&v.to_le_bytes()),
        false => out.extend_from_slice(&(v as u32).to_le_bytes()),
    };
    let encoded: Vec<(u16, Encoded)> = entries
        .iter()
        .map(|(tag, v)| (*tag, v.encode(big)))
        .collect();
    let mut out = Vec::new();
    match big {
        true => out.extend_from_slice(&(entries.len() as u64).to_le_bytes()),
        false => out.extend_from_slice(&(entries.len() as u16).to_le_bytes()),
    }
    let directory_end = at + (count_bytes + entry_bytes * entries.len() + inline) as u64;
    let mut extra = Vec::new();
    for (tag, (kind, count, bytes)) in &encoded {
        out.extend_from_slice(&tag.to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        offset(*count, &mut out);
        if bytes.len() <= inline {
            let mut field = bytes.clone();
            field.resize(inline, 0);
            out.extend_from_slice(&field);
        } else {
            offset(directory_end + extra.len() as u64, &mut out);
            extra.extend_from_slice(bytes);
            // Values start on a word boundary.
            if extra.len() % 2 == 1 {
                extra.push(0);
            }
        }
    }
    offset(next, &mut out);
    debug_assert_eq!(at + out.len() as u64, directory_end);
    out.extend_from_slice(&extra);
    out
}
