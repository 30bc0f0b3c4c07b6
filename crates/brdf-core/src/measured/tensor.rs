//! Mitsuba's tensor file: a little-endian container of named n-dimensional arrays, the file format of
//! the RGL material database's `.bsdf` files ([`super::RglBsdf`]). Layout (Mitsuba 3,
//! `include/mitsuba/core/tensor.h`, `src/core/tensor.cpp` and `mitsuba.tensor_io`):
//!
//! | bytes | content |
//! |---|---|
//! | 12 | magic `"tensor_file\0"` |
//! | 2 | version, `u8` major = 1, `u8` minor = 0 |
//! | 4 | `u32` number of fields |
//! | per field | `u16` name length, the UTF-8 name, `u16` rank, `u8` dtype, `u64` byte offset of the data from the start of the file, `rank` × `u64` shape |
//! | … | each field's data, C order (last index fastest), at its offset |
//!
//! dtypes (Mitsuba's `Struct::Type`): 1 `u8`, 2 `i8`, 3 `u16`, 4 `i16`, 5 `u32`, 6 `i32`, 7 `u64`,
//! 8 `i64`, 9 `f16`, 10 `f32`, 11 `f64`. [`TensorFile::write`] pads each field's data to 8-byte
//! alignment, as `mitsuba.tensor_io.write` does.
//!
//! Every size the header states is checked against the bytes that are there before anything is
//! allocated: a header cannot ask for more memory than the file holds.

use crate::BrdfError;

/// Element type of a [`TensorField`] (Mitsuba's `Struct::Type` codes, see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DType {
    /// `u8` (code 1).
    U8,
    /// `i8` (2).
    I8,
    /// `u16` (3).
    U16,
    /// `i16` (4).
    I16,
    /// `u32` (5).
    U32,
    /// `i32` (6).
    I32,
    /// `u64` (7).
    U64,
    /// `i64` (8).
    I64,
    /// IEEE half (9).
    F16,
    /// `f32` (10).
    F32,
    /// `f64` (11).
    F64,
}

impl DType {
    /// The code in the file.
    pub fn code(self) -> u8 {
        self as u8 + 1
    }

    /// From the code in the file.
    pub fn from_code(code: u8) -> Option<Self> {
        use DType::*;
        [U8, I8, U16, I16, U32, I32, U64, I64, F16, F32, F64].get(usize::from(code).checked_sub(1)?).copied()
    }

    /// Bytes per element.
    pub fn size(self) -> usize {
        use DType::*;
        match self {
            U8 | I8 => 1,
            U16 | I16 | F16 => 2,
            U32 | I32 | F32 => 4,
            U64 | I64 | F64 => 8,
        }
    }
}

/// One named array of a tensor file: its type, its shape and its raw little-endian bytes.
#[derive(Debug, Clone, PartialEq)]
pub struct TensorField {
    /// The field's name.
    pub name: String,
    /// Element type.
    pub dtype: DType,
    /// Extent along each axis, C order.
    pub shape: Vec<usize>,
    /// `shape.iter().product() * dtype.size()` bytes, little-endian, C order.
    pub bytes: Vec<u8>,
}

impl TensorField {
    /// A `f32` field.
    pub fn f32(name: &str, shape: Vec<usize>, values: &[f32]) -> Self {
        debug_assert_eq!(shape.iter().product::<usize>(), values.len());
        let bytes = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        Self { name: name.to_string(), dtype: DType::F32, shape, bytes }
    }

    /// A `u8` field.
    pub fn u8(name: &str, shape: Vec<usize>, values: &[u8]) -> Self {
        Self { name: name.to_string(), dtype: DType::U8, shape, bytes: values.to_vec() }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.shape.iter().product()
    }

    /// Whether the field holds no element.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The values of a `f32` field; an error naming the field for another dtype.
    pub fn to_f32(&self) -> Result<Vec<f32>, BrdfError> {
        if self.dtype != DType::F32 {
            return Err(bad(format!("field {:?} must be float32, is {:?}", self.name, self.dtype)));
        }
        Ok(self.bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect())
    }
}

fn bad(problem: String) -> BrdfError {
    BrdfError::InvalidInput { name: "tensor file", problem }
}

/// The magic bytes a tensor file starts with.
pub const MAGIC: &[u8; 12] = b"tensor_file\0";

/// Largest rank a field may declare (Mitsuba has no limit; the RGL files use at most 5).
pub const MAX_RANK: usize = 16;

/// A parsed tensor file: its fields in the order of the header.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TensorFile {
    /// The fields.
    pub fields: Vec<TensorField>,
}

/// A cursor over the header that refuses to read past the end of the file.
struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], BrdfError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len()).ok_or_else(|| {
            bad(format!(
                "truncated: {what} needs {n} bytes at offset {}, the file has {}",
                self.pos,
                self.bytes.len()
            ))
        })?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn u16(&mut self, what: &str) -> Result<u16, BrdfError> {
        let b = self.take(2, what)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }
    fn u32(&mut self, what: &str) -> Result<u32, BrdfError> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn u64(&mut self, what: &str) -> Result<u64, BrdfError> {
        let mut a = [0u8; 8];
        a.copy_from_slice(self.take(8, what)?);
        Ok(u64::from_le_bytes(a))
    }
}

impl TensorFile {
    /// The field named `name`, or an error naming it.
    pub fn field(&self, name: &str) -> Result<&TensorField, BrdfError> {
        self.fields.iter().find(|f| f.name == name).ok_or_else(|| {
            let known: Vec<&str> = self.fields.iter().map(|f| f.name.as_str()).collect();
            bad(format!("no field {name:?} (fields: {})", known.join(", ")))
        })
    }

    /// Whether a field of that name exists.
    pub fn has_field(&self, name: &str) -> bool {
        self.fields.iter().any(|f| f.name == name)
    }

    /// Parse a tensor file (layout in the module docs). Refuses a wrong magic or version, an unknown
    /// dtype, a rank above [`MAX_RANK`], duplicate names, non-UTF-8 names, and any field whose data
    /// (offset + product of the shape × element size, overflow-checked) does not lie inside `bytes`.
    pub fn read(bytes: &[u8]) -> Result<Self, BrdfError> {
        let mut c = Cursor { bytes, pos: 0 };
        let magic = c.take(12, "the magic")?;
        if magic != MAGIC {
            return Err(bad(format!(
                "wrong magic: expected \"tensor_file\\0\", found {:?}",
                String::from_utf8_lossy(magic)
            )));
        }
        let version = c.take(2, "the version")?;
        if version != [1, 0] {
            return Err(bad(format!("unknown version {}.{} (expected 1.0)", version[0], version[1])));
        }
        let n_fields = c.u32("the field count")? as usize;
        // Each field header takes at least 2 + 2 + 1 + 8 = 13 bytes: the count cannot exceed that.
        if n_fields > bytes.len() / 13 {
            return Err(bad(format!("the header declares {n_fields} fields, more than the file can hold")));
        }
        let mut fields = Vec::with_capacity(n_fields);
        for i in 0..n_fields {
            let name_len = c.u16(&format!("the name length of field {i}"))? as usize;
            let name = std::str::from_utf8(c.take(name_len, &format!("the name of field {i}"))?)
                .map_err(|_| bad(format!("the name of field {i} is not UTF-8")))?
                .to_string();
            let rank = c.u16(&format!("the rank of field {name:?}"))? as usize;
            if rank > MAX_RANK {
                return Err(bad(format!("field {name:?} has rank {rank}, more than {MAX_RANK}")));
            }
            let code = c.take(1, &format!("the dtype of field {name:?}"))?[0];
            let dtype = DType::from_code(code)
                .ok_or_else(|| bad(format!("field {name:?} has unknown dtype {code}")))?;
            let offset = c.u64(&format!("the offset of field {name:?}"))?;
            let mut shape = Vec::with_capacity(rank);
            let mut size = dtype.size() as u64;
            for a in 0..rank {
                let s = c.u64(&format!("the shape of field {name:?}"))?;
                size = size
                    .checked_mul(s)
                    .ok_or_else(|| bad(format!("field {name:?}: the shape overflows (axis {a} is {s})")))?;
                shape.push(s as usize);
            }
            let end = offset.checked_add(size).filter(|&e| e <= bytes.len() as u64).ok_or_else(|| {
                bad(format!(
                    "truncated: field {name:?} ({dtype:?} {shape:?}) needs bytes {offset}..{} , the file has {}",
                    offset as u128 + size as u128,
                    bytes.len()
                ))
            })?;
            if fields.iter().any(|f: &TensorField| f.name == name) {
                return Err(bad(format!("field {name:?} appears twice")));
            }
            let data = bytes[offset as usize..end as usize].to_vec();
            fields.push(TensorField { name, dtype, shape, bytes: data });
        }
        Ok(Self { fields })
    }

    /// The file's bytes: header, then each field's data at the next multiple of 8 bytes.
    pub fn write(&self) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&[1, 0]);
        out.extend_from_slice(&(self.fields.len() as u32).to_le_bytes());
        let mut offset_at = Vec::with_capacity(self.fields.len());
        for f in &self.fields {
            out.extend_from_slice(&(f.name.len() as u16).to_le_bytes());
            out.extend_from_slice(f.name.as_bytes());
            out.extend_from_slice(&(f.shape.len() as u16).to_le_bytes());
            out.push(f.dtype.code());
            offset_at.push(out.len());
            out.extend_from_slice(&0u64.to_le_bytes());
            for &s in &f.shape {
                out.extend_from_slice(&(s as u64).to_le_bytes());
            }
        }
        for (f, &at) in self.fields.iter().zip(&offset_at) {
            out.resize(out.len().div_ceil(8) * 8, 0);
            let pos = out.len() as u64;
            out[at..at + 8].copy_from_slice(&pos.to_le_bytes());
            out.extend_from_slice(&f.bytes);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> TensorFile {
        TensorFile {
            fields: vec![
                TensorField::u8("description", vec![5], b"hello"),
                TensorField::f32("grid", vec![2, 3], &[0.0, 1.0, 2.0, 3.0, 4.5, -1.0]),
            ],
        }
    }

    #[test]
    fn round_trips_with_aligned_data() {
        let t = sample();
        let bytes = t.write();
        assert_eq!(&bytes[..12], MAGIC);
        assert_eq!(&bytes[12..18], &[1, 0, 2, 0, 0, 0]);
        let back = TensorFile::read(&bytes).unwrap();
        assert_eq!(back, t);
        assert_eq!(back.field("grid").unwrap().to_f32().unwrap()[4], 4.5);
        // The data of the second field starts on an 8-byte boundary.
        let g = bytes.windows(4).position(|w| w == 4.5f32.to_le_bytes()).unwrap() - 16;
        assert_eq!(g % 8, 0);
    }

    #[test]
    fn refuses_corrupt_headers_without_allocating_what_they_claim() {
        let bytes = sample().write();
        for cut in [0, 5, 13, 17, 20, 30, bytes.len() - 1] {
            let e = TensorFile::read(&bytes[..cut]).unwrap_err().to_string();
            assert!(e.contains("truncated") || e.contains("fields"), "cut {cut}: {e}");
        }
        let mut b = bytes.clone();
        b[0] = b'T';
        assert!(TensorFile::read(&b).unwrap_err().to_string().contains("magic"));
        let mut b = bytes.clone();
        b[12] = 2;
        assert!(TensorFile::read(&b).unwrap_err().to_string().contains("version 2.0"));
        let mut b = bytes.clone();
        b[14..18].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(TensorFile::read(&b).unwrap_err().to_string().contains("more than the file"));
        // The first field's shape claims 2^62 elements.
        let mut b = bytes.clone();
        let shape_at = 18 + 2 + 11 + 2 + 1 + 8;
        b[shape_at..shape_at + 8].copy_from_slice(&(1u64 << 62).to_le_bytes());
        let e = TensorFile::read(&b).unwrap_err().to_string();
        assert!(e.contains("truncated") && e.contains("description"), "{e}");
        // Unknown dtype.
        let mut b = bytes.clone();
        b[18 + 2 + 11 + 2] = 12;
        assert!(TensorFile::read(&b).unwrap_err().to_string().contains("unknown dtype 12"));
        assert!(sample().field("nope").unwrap_err().to_string().contains("description, grid"));
    }
}
