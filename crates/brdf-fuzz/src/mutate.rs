//! A coverage-free mutation engine (stable Rust, no compiler instrumentation): each input is a corpus
//! file changed by a few random edits of the kinds libFuzzer and AFL use — bit flips, interesting
//! integers, inserted / erased / duplicated / spliced byte runs, format tokens from a dictionary, and
//! textual numbers replaced by hostile ones (`-1`, `4294967296`, `nan`, `1e39`, ...).
//!
//! Everything follows from one 64-bit seed ([`SplitMix64`]), so a run is reproduced exactly by its
//! seed and execution index: the driver relies on this to find the input that crashed a child process.

/// SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014).
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator started from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (`n > 0`; the modulo bias is irrelevant here).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }

    /// True with probability `1 / n`.
    pub fn one_in(&mut self, n: usize) -> bool {
        self.below(n) == 0
    }
}

/// Integers that break size arithmetic, as little-endian bytes of 1, 2, 4 or 8.
const INTERESTING: [u64; 16] = [
    0,
    1,
    2,
    3,
    0x7F,
    0x80,
    0xFF,
    0x7FFF,
    0xFFFF,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFF,
    0x1_0000_0000,
    0x7FFF_FFFF_FFFF_FFFF,
    0xFFFF_FFFF_FFFF_FFFF,
    4096,
];

/// Numbers written as text that readers must refuse or survive.
const HOSTILE_NUMBERS: [&str; 24] = [
    "0",
    "-0",
    "1",
    "-1",
    "2",
    "-2147483649",
    "2147483648",
    "4294967295",
    "4294967296",
    "18446744073709551616",
    "99999999999999999999999",
    "1e39",
    "-1e39",
    "1e-45",
    "3.4028235e38",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "0x10",
    "1.5",
    "",
    "+",
    "--1",
];

/// A mutator over the inputs of one target.
#[derive(Debug, Clone)]
pub struct Mutator {
    rng: SplitMix64,
    dictionary: &'static [&'static [u8]],
    max_len: usize,
}

impl Mutator {
    /// A mutator seeded with `seed`, inserting tokens from `dictionary`, keeping inputs to `max_len`
    /// bytes.
    pub fn new(seed: u64, dictionary: &'static [&'static [u8]], max_len: usize) -> Self {
        Self { rng: SplitMix64::new(seed), dictionary, max_len }
    }

    /// The generator (the driver draws its corpus picks from the same stream).
    pub fn rng(&mut self) -> &mut SplitMix64 {
        &mut self.rng
    }

    /// Replace `data` by a mutant of it: 1 to 8 stacked edits, `other` supplying splices.
    pub fn mutate(&mut self, data: &mut Vec<u8>, other: &[u8]) {
        let edits = 1 + self.rng.below(8);
        for _ in 0..edits {
            self.edit(data, other);
        }
        data.truncate(self.max_len);
    }

    fn edit(&mut self, data: &mut Vec<u8>, other: &[u8]) {
        let len = data.len();
        match self.rng.below(11) {
            0 if len > 0 => {
                let i = self.rng.below(len);
                data[i] ^= 1 << self.rng.below(8);
            }
            1 if len > 0 => {
                let i = self.rng.below(len);
                data[i] = self.rng.next_u64() as u8;
            }
            2 if len > 0 => {
                let width = [1, 2, 4, 8][self.rng.below(4)];
                let value = INTERESTING[self.rng.below(INTERESTING.len())];
                let value = if self.rng.one_in(2) { value } else { value.wrapping_neg() };
                let bytes = value.to_le_bytes();
                let bytes = if self.rng.one_in(3) { value.swap_bytes().to_le_bytes() } else { bytes };
                let at = self.rng.below(len);
                for (k, b) in bytes[..width].iter().enumerate() {
                    if let Some(slot) = data.get_mut(at + k) {
                        *slot = *b;
                    }
                }
            }
            3 => {
                let token = self.dictionary[self.rng.below(self.dictionary.len())];
                let at = self.rng.below(len + 1);
                data.splice(at..at, token.iter().copied());
            }
            4 if len > 0 => {
                let (start, end) = self.range(len);
                data.drain(start..end);
            }
            5 if len > 0 => {
                let (start, end) = self.range(len);
                let run: Vec<u8> = data[start..end].to_vec();
                let at = self.rng.below(len + 1);
                data.splice(at..at, run);
            }
            6 if !other.is_empty() => {
                let (start, end) = self.range(other.len());
                let at = self.rng.below(len + 1);
                let cut = if self.rng.one_in(2) { len } else { at };
                data.truncate(cut.max(at));
                data.splice(at.min(data.len())..at.min(data.len()), other[start..end].iter().copied());
            }
            7 => self.replace_number(data),
            8 if len > 0 => data.truncate(self.rng.below(len)),
            9 if len > 0 => {
                // Repeat a run many times: long lines, huge lists, deep repetition.
                let (start, end) = self.range(len.min(64));
                let run: Vec<u8> = data[start..end].to_vec();
                let times = 1 + self.rng.below(256);
                let at = self.rng.below(len + 1);
                let repeated: Vec<u8> = run.iter().copied().cycle().take(run.len() * times).collect();
                data.splice(at..at, repeated);
            }
            _ => {
                let at = self.rng.below(len + 1);
                data.insert(at, self.rng.next_u64() as u8);
            }
        }
    }

    /// A random non-empty range `start..end` of `0..len` (short runs more often than long ones).
    fn range(&mut self, len: usize) -> (usize, usize) {
        let start = self.rng.below(len);
        let max = (len - start).min(if self.rng.one_in(4) { len } else { 16 });
        (start, start + 1 + self.rng.below(max.max(1)).min(len - start - 1))
    }

    /// Replace one run of number characters (digits, sign, dot, exponent) by a hostile number.
    fn replace_number(&mut self, data: &mut Vec<u8>) {
        let is_num = |b: u8| b.is_ascii_digit() || b == b'-' || b == b'.' || b == b'e' || b == b'+';
        let starts: Vec<usize> =
            (0..data.len()).filter(|&i| is_num(data[i]) && (i == 0 || !is_num(data[i - 1]))).collect();
        if starts.is_empty() {
            return;
        }
        let start = starts[self.rng.below(starts.len())];
        let end = (start..data.len()).find(|&i| !is_num(data[i])).unwrap_or(data.len());
        let number = HOSTILE_NUMBERS[self.rng.below(HOSTILE_NUMBERS.len())];
        data.splice(start..end, number.bytes());
    }
}

/// Tokens of each format, inserted by [`Mutator`].
pub fn dictionary(target: crate::Target) -> &'static [&'static [u8]] {
    use crate::Target;
    match target {
        Target::Obj => &[
            b"v ",
            b"vn ",
            b"vt ",
            b"f ",
            b"l ",
            b"p ",
            b"o ",
            b"g ",
            b"s off",
            b"usemtl m",
            b"mtllib x.mtl",
            b"/",
            b"//",
            b" -1",
            b" 0",
            b" 4294967296",
            b" nan",
            b" inf",
            b"\n",
            b"\r\n",
            b"\\\n",
            b"#",
            b"f 1 2 3\n",
            b"f -1 -2 -3\n",
            b"f 1/1/1 2/2/2 3/3/3\n",
            b"v 0 0 0\n",
            b"vn 0 0 0\n",
            b"v 1 2 3 0.5 0.5 0.5\n",
            b"\t",
            b"\xef\xbb\xbf",
        ],
        Target::Ply => &[
            b"ply\n",
            b"format ascii 1.0\n",
            b"format binary_little_endian 1.0\n",
            b"format binary_big_endian 1.0\n",
            b"element vertex ",
            b"element face ",
            b"element edge 1\n",
            b"property float x\n",
            b"property double y\n",
            b"property uchar red\n",
            b"property float nx\n",
            b"property list uchar int vertex_indices\n",
            b"property list uint int vertex_index\n",
            b"property list int uchar vertex_indices\n",
            b"end_header\n",
            b"comment c\n",
            b"obj_info o\n",
            b" 18446744073709551615",
            b" 4294967295",
            b" -1",
            b" 0",
            b" 255",
            b"\r\n",
            b"\n",
        ],
        Target::Stl => &[
            b"solid s\n",
            b"facet normal 0 0 1\n",
            b"outer loop\n",
            b"vertex 0 0 0\n",
            b"vertex 1 0 0\n",
            b"endloop\n",
            b"endfacet\n",
            b"endsolid s\n",
            b" nan",
            b" 1e39",
            b"\xff\xff\xff\xff",
            b"\x01\x00\x00\x00",
            b"\x00\x00\x80\x7f",
        ],
        Target::Merl => &[
            b"\x5a\x00\x00\x00",
            b"\xb4\x00\x00\x00",
            b"\x02\x00\x00\x00",
            b"\x00\x10\x00\x00",
            b"\x01\x10\x00\x00",
            b"\xff\xff\xff\xff",
            b"\x00\x00\x00\x80",
            b"\x00\x00\x00\x00\x00\x00\xf0\x7f",
            b"\x00\x00\x00\x00\x00\x00\xf8\x7f",
            b"\x00\x00\x00\x00\x00\x00\xf0\xbf",
            b"\x00\x00\x00\x00\x00\x00\x00\x00",
        ],
        Target::MitDat => &[
            b"\x2d\x00\x00\x00",
            b"\xb4\x00\x00\x00",
            b"\x5a\x00\x00\x00",
            b"\x01\x00\x00\x00",
            b"\x03\x00\x00\x00",
            b"\x00\x10\x00\x00",
            b"\x01\x10\x00\x00",
            b"\xff\xff\xff\xff",
            b"\x00\x00\x00\x80",
            b"\x00\x00\x80\xbf",
            b"\x00\x00\xc0\x7f",
            b"\x00\x00\x80\x7f",
            b"\xff\xff\x7f\x7f",
        ],
        Target::Mesh => &[
            b"\x00",
            b"\x01",
            b"\xff",
            b"\x00\x00\xc0\x7f",
            b"\x00\x00\x80\x7f",
            b"\xff\xff\x7f\x7f",
            b"\x01\x00\x00\x00",
            b"\x00\x00\x80\x3f",
            b"\x00\x00\x00\x00",
        ],
        Target::Gltf => &[
            b"\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4294967295,\"type\":\"VEC3\"}]",
            b"\"byteOffset\":4294967295",
            b"\"byteStride\":3",
            b"\"count\":0",
            b"\"componentType\":5121",
            b"\"componentType\":5125",
            b"\"type\":\"MAT4\"",
            b"\"mode\":0",
            b"\"mode\":5",
            b"\"sparse\":{\"count\":1}",
            b"\"children\":[0]",
            b"\"matrix\":[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]",
            b"\"scale\":[1e39,0,-0]",
            b"\"rotation\":[0,0,0,0]",
            b"\"uri\":\"data:application/octet-stream;base64,AAAA\"",
            b"\"uri\":\"../../etc/passwd\"",
            b"\"baseColorFactor\":[2,-1,1e39,1]",
            b"\"roughnessFactor\":-3",
            b"\"yfov\":0",
            b"\"intensity\":-1",
            b"1e39",
            b"-1",
            b"null",
            b"glTF",
            b"JSON",
            b"BIN\x00",
            b"\xff\xff\xff\xff",
        ],
        Target::Hdr => &[
            b"#?RADIANCE\n",
            b"#?RGBE\n",
            b"FORMAT=32-bit_rle_rgbe\n",
            b"FORMAT=32-bit_rle_xyze\n",
            b"EXPOSURE=0\n",
            b"\n-Y 2 +X 4\n",
            b"-Y 65535 +X 65535\n",
            b"+Y 3 -X 16\n",
            b"-Y 0 +X 0\n",
            b"\x02\x02\x00\x10",
            b"\x02\x02\x7f\xff",
            b"\x90\xff",
            b"\xff\xff\xff\xff",
            b"\x01\x01\x01",
        ],
        Target::Exr => &[
            b"\x76\x2f\x31\x01",
            b"channels\x00chlist\x00",
            b"compression\x00compression\x00",
            b"dataWindow\x00box2i\x00",
            b"displayWindow\x00box2i\x00",
            b"lineOrder\x00lineOrder\x00",
            b"tiles\x00tiledesc\x00",
            b"\x00\x00\x00\x00",
            b"\xff\xff\xff\x7f",
            b"\x00\x00\x00\x80",
            b"\x01\x00\x00\x00",
            b"\x02\x00\x00\x00",
            b"\x00\x7c",
            b"\x00\xfe",
        ],
    }
}
