//! Mitsuba's tensor file, the container of RGL's `.bsdf` files: the 12 bytes `tensor_file\0`, the version
//! (1, 0), a `u32` count of fields, then per field its name (`u16` length and UTF-8 bytes), its rank
//! (`u16`), its type (`u8`, Mitsuba's `Struct::Type` numbering: 1 uint8 ... 10 float32, 11 float64), the
//! offset of its data from the file's start (`u64`) and its shape (a `u64` per dimension, the last one
//! contiguous), all little-endian. Read here from that definition; an RGL file's fields are uint8 and
//! float32, and only those are taken.

use std::collections::BTreeMap;

/// The file's first bytes.
pub const MAGIC: &[u8; 12] = b"tensor_file\0";

/// `Struct::Type`'s codes of the two types an RGL file holds.
const UINT8: u8 = 1;
const FLOAT32: u8 = 10;

/// Past these a file is refused as damaged: the fields, a name's bytes, a field's rank.
const MAX_FIELDS: u32 = 64;
const MAX_NAME_BYTES: u16 = 256;
const MAX_RANK: u16 = 8;

/// A field's values.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    /// uint8 (a text's bytes, a flag).
    Bytes(Vec<u8>),
    /// float32, each finite.
    Floats(Vec<f32>),
}

/// One field: its shape (the last dimension contiguous) and values.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Its size along each dimension.
    pub shape: Vec<usize>,
    /// Its values, row by row (the last dimension contiguous).
    pub values: Values,
}

impl Field {
    /// A float32 field.
    pub fn floats(shape: Vec<usize>, values: Vec<f32>) -> Self {
        Self { shape, values: Values::Floats(values) }
    }

    /// A uint8 field of one dimension.
    pub fn bytes(values: Vec<u8>) -> Self {
        Self { shape: vec![values.len()], values: Values::Bytes(values) }
    }
}

/// A tensor file's fields by name.
pub type Fields = BTreeMap<String, Field>;

/// Reads a tensor file's fields.
///
/// # Errors
/// What is wrong, in one line: the magic, the version, a field's type, a shape that overflows or runs past
/// the file's end, a float that is not finite (NaN or infinite), a header cut short.
pub fn parse(bytes: &[u8]) -> Result<Fields, String> {
    if bytes.len() < 18 || &bytes[..12] != MAGIC {
        return Err("not a tensor file (it does not begin with `tensor_file`)".into());
    }
    if bytes[12..14] != [1, 0] {
        return Err(format!("tensor file version {}.{}: only 1.0 is known", bytes[12], bytes[13]));
    }
    let mut at = 14;
    let count = u32::from_le_bytes(take(bytes, &mut at)?);
    if count > MAX_FIELDS {
        return Err(format!("{count} fields: more than {MAX_FIELDS}, the file is damaged"));
    }
    let mut fields = Fields::new();
    for _ in 0..count {
        let name_bytes = u16::from_le_bytes(take(bytes, &mut at)?);
        if name_bytes > MAX_NAME_BYTES {
            return Err(format!("a field's name of {name_bytes} bytes: the file is damaged"));
        }
        let name = bytes
            .get(at..at + usize::from(name_bytes))
            .and_then(|b| std::str::from_utf8(b).ok())
            .ok_or("a field's name is cut short or not UTF-8")?
            .to_string();
        at += usize::from(name_bytes);
        let rank = u16::from_le_bytes(take(bytes, &mut at)?);
        let [dtype] = take::<1>(bytes, &mut at)?;
        let offset = u64::from_le_bytes(take(bytes, &mut at)?);
        if rank > MAX_RANK {
            return Err(format!("field `{name}`: rank {rank}, more than {MAX_RANK}"));
        }
        let mut shape = Vec::with_capacity(usize::from(rank));
        for _ in 0..rank {
            shape.push(u64::from_le_bytes(take(bytes, &mut at)?));
        }
        let field = read_field(bytes, &name, dtype, offset, &shape)?;
        fields.insert(name, field);
    }
    Ok(fields)
}

fn take<const N: usize>(bytes: &[u8], at: &mut usize) -> Result<[u8; N], String> {
    let read = bytes.get(*at..*at + N).ok_or("the header is cut short")?;
    *at += N;
    Ok(read.try_into().unwrap_or([0; N]))
}

fn read_field(bytes: &[u8], name: &str, dtype: u8, offset: u64, shape: &[u64]) -> Result<Field, String> {
    let width = match dtype {
        UINT8 => 1,
        FLOAT32 => 4,
        other => return Err(format!("field `{name}`: type code {other}; an RGL file's fields are uint8 or float32")),
    };
    let count = shape.iter().try_fold(1u64, |n, &d| n.checked_mul(d));
    let end = count.and_then(|n| n.checked_mul(width)).and_then(|b| b.checked_add(offset));
    let data = end
        .filter(|&end| end <= bytes.len() as u64)
        .map(|end| &bytes[offset as usize..end as usize])
        .ok_or_else(|| format!("field `{name}`: its shape {shape:?} runs past the file's end"))?;
    let shape = shape.iter().map(|&d| d as usize).collect();
    let values = if dtype == UINT8 {
        Values::Bytes(data.to_vec())
    } else {
        let floats: Vec<f32> = data.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
        if let Some(k) = floats.iter().position(|v| !v.is_finite()) {
            return Err(format!("field `{name}`: value {k} is {}", floats[k]));
        }
        Values::Floats(floats)
    };
    Ok(Field { shape, values })
}

/// The bytes of a tensor file holding `fields` (in their order), their data after the header.
pub fn write(fields: &Fields) -> Vec<u8> {
    let header: usize =
        18 + fields.iter().map(|(name, f)| 2 + name.len() + 2 + 1 + 8 + 8 * f.shape.len()).sum::<usize>();
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&(fields.len() as u32).to_le_bytes());
    let mut offset = header as u64;
    for (name, field) in fields {
        out.extend_from_slice(&(name.len() as u16).to_le_bytes());
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(&(field.shape.len() as u16).to_le_bytes());
        let (dtype, bytes) = match &field.values {
            Values::Bytes(b) => (UINT8, b.len()),
            Values::Floats(f) => (FLOAT32, 4 * f.len()),
        };
        out.push(dtype);
        out.extend_from_slice(&offset.to_le_bytes());
        for &d in &field.shape {
            out.extend_from_slice(&(d as u64).to_le_bytes());
        }
        offset += bytes as u64;
    }
    for field in fields.values() {
        match &field.values {
            Values::Bytes(b) => out.extend_from_slice(b),
            Values::Floats(f) => f.iter().for_each(|v| out.extend_from_slice(&v.to_le_bytes())),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> Fields {
        let mut fields = Fields::new();
        fields.insert("description".into(), Field::bytes(b"two by three".to_vec()));
        fields.insert("values".into(), Field::floats(vec![2, 3], vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.5]));
        fields
    }

    #[test]
    fn a_file_reads_back_as_written_byte_by_byte() {
        let bytes = write(&example());
        // The header by hand: magic, version, 2 fields; "description": name 11 bytes, rank 1, uint8, offset,
        // 12; "values": rank 2, float32, its offset 12 bytes after the first's data.
        let header = 18 + (2 + 11 + 2 + 1 + 8 + 8) + (2 + 6 + 2 + 1 + 8 + 16);
        assert_eq!(&bytes[..12], b"tensor_file\0");
        assert_eq!(&bytes[12..18], &[1, 0, 2, 0, 0, 0]);
        assert_eq!(&bytes[18..20], &[11, 0]);
        assert_eq!(u64::from_le_bytes(bytes[34..42].try_into().unwrap()), header as u64);
        assert_eq!(bytes.len(), header + 12 + 24);
        assert_eq!(&bytes[header..header + 12], b"two by three");
        assert_eq!(parse(&bytes).unwrap(), example());
    }

    #[test]
    fn damaged_files_are_refused_in_one_line() {
        let bytes = write(&example());
        assert!(parse(b"MERL binary file").unwrap_err().contains("not a tensor file"));
        let mut version = bytes.clone();
        version[12] = 2;
        assert!(parse(&version).unwrap_err().contains("version 2.0"));
        assert!(parse(&bytes[..30]).unwrap_err().contains("cut short"));
        assert!(parse(&bytes[..bytes.len() - 1]).unwrap_err().contains("`values`: its shape [2, 3] runs past"));
        let mut nan = bytes.clone();
        let last = nan.len() - 4;
        nan[last..].copy_from_slice(&f32::NAN.to_le_bytes());
        assert!(parse(&nan).unwrap_err().contains("`values`: value 5 is NaN"));
        let mut double = bytes.clone();
        double[18 + 2 + 11 + 2] = 11;
        assert!(parse(&double).unwrap_err().contains("type code 11"));
        // A shape whose size overflows.
        let mut huge = bytes;
        let at = 18 + (2 + 11 + 2 + 1 + 8 + 8) + 2 + 6 + 2 + 1 + 8;
        huge[at..at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(parse(&huge).unwrap_err().contains("runs past the file's end"));
    }
}
