//! Shapes and NumPy broadcasting of the leading dimensions, and the map from an output element to the
//! input element it reads.

use std::fmt;

use crate::BrdfError;

/// The most leading dimensions an input may have (NumPy allowed 32 until 2.0; more is never needed
/// here and keeps [`Shape`] a small `Copy` value).
pub const MAX_DIMS: usize = 32;

/// The most elements one batch may have: 2³² (4 294 967 296). A broadcast shape with more is refused
/// with an error naming the input that took it past the limit, before anything is allocated: its output
/// alone would be 16 GiB of numbers (48 GiB of vectors), more than any machine this runs on gives one
/// array, and the attempt would end in an allocation failure, i.e. an abort, rather than an error. Split
/// such a batch into parts.
pub const MAX_BATCH_LEN: usize = 1 << 32;

/// The shape of a batch or of one input **without** its item axis: `(90, 360)` for a `(90, 360, 3)`
/// array of directions, `()` for a single direction `(3,)`, `(N,)` for N rows.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Shape {
    ndim: usize,
    dims: [usize; MAX_DIMS],
}

impl Shape {
    /// The shape of one element, `()`.
    pub const SCALAR: Shape = Shape { ndim: 0, dims: [1; MAX_DIMS] };

    /// `dims` as a shape; `None` beyond [`MAX_DIMS`] dimensions.
    pub fn new(dims: &[usize]) -> Option<Shape> {
        if dims.len() > MAX_DIMS {
            return None;
        }
        let mut s = Shape { ndim: dims.len(), dims: [1; MAX_DIMS] };
        s.dims[..dims.len()].copy_from_slice(dims);
        Some(s)
    }

    /// `(n,)`: `n` rows.
    pub fn rows(n: usize) -> Shape {
        let mut s = Shape::SCALAR;
        s.ndim = 1;
        s.dims[0] = n;
        s
    }

    /// The dimensions.
    pub fn dims(&self) -> &[usize] {
        &self.dims[..self.ndim]
    }

    /// The number of dimensions.
    pub fn ndim(&self) -> usize {
        self.ndim
    }

    /// The number of elements (the product of the dimensions; 1 for `()`). Saturates at `usize::MAX`
    /// (such a shape can only come from broadcasting, which refuses it).
    pub fn len(&self) -> usize {
        self.dims().iter().try_fold(1usize, |a, &d| a.checked_mul(d)).unwrap_or(usize::MAX)
    }

    /// `true` when the shape has no element (some dimension is 0).
    pub fn is_empty(&self) -> bool {
        self.dims().contains(&0)
    }

    /// The dimensions followed by `item` (e.g. `[3]` for the output of directions or colors), for
    /// allocating an array of this shape.
    pub fn with_item(&self, item: &[usize]) -> Vec<usize> {
        let mut v = self.dims().to_vec();
        v.extend_from_slice(item);
        v
    }

    /// The multi-index of element `flat` (C order).
    pub fn unravel(&self, mut flat: usize) -> Vec<usize> {
        let mut idx = vec![0; self.ndim];
        for (i, &d) in idx.iter_mut().zip(self.dims()).rev() {
            *i = flat % d.max(1);
            flat /= d.max(1);
        }
        idx
    }
}

impl fmt::Debug for Shape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&tuple(self.dims(), &[]))
    }
}

/// `dims` and `item` as a Python tuple: `(5, 3)`, `(3,)`, `()`.
pub(crate) fn tuple(dims: &[usize], item: &[usize]) -> String {
    let all: Vec<String> = dims.iter().chain(item).map(|d| d.to_string()).collect();
    match all.len() {
        1 => format!("({},)", all[0]),
        _ => format!("({})", all.join(", ")),
    }
}

/// One input's name, shape and item shape (for broadcasting and messages).
#[derive(Debug, Clone, Copy)]
pub struct ShapeOf<'a> {
    /// The argument's name as the caller knows it.
    pub name: &'static str,
    /// Its shape without the item axis.
    pub shape: &'a Shape,
    /// Its item shape (`[3]` for vectors, `[]` for numbers), shown in messages.
    pub item: &'static [usize],
}

/// The shape of a batch whose inputs have the given shapes, by NumPy's rule for the leading
/// dimensions: align them at the right (a missing dimension counts as 1); in each position the sizes
/// must be equal or 1, and the result has the larger one. The message names the first input that does
/// not fit and the shape it was broadcast against. A result of more than [`MAX_BATCH_LEN`] elements is
/// refused, naming the input that took it past the limit.
pub fn broadcast(inputs: &[ShapeOf<'_>]) -> Result<Shape, BrdfError> {
    let mut out = Shape::SCALAR;
    let mut from: Vec<&str> = Vec::new();
    for s in inputs {
        let (a, b) = (out.dims(), s.shape.dims());
        let ndim = a.len().max(b.len());
        let mut next = Shape { ndim, dims: [1; MAX_DIMS] };
        let mut ok = true;
        for k in 0..ndim {
            let da = if k + a.len() >= ndim { a[k + a.len() - ndim] } else { 1 };
            let db = if k + b.len() >= ndim { b[k + b.len() - ndim] } else { 1 };
            next.dims[k] = match (da, db) {
                (x, y) if x == y => x,
                (1, y) => y,
                (x, 1) => x,
                _ => {
                    ok = false;
                    1
                }
            };
        }
        if !ok {
            let against = tuple(out.dims(), s.item);
            return Err(BrdfError::InvalidInput {
                name: s.name,
                problem: format!(
                    "has shape {}, which does not broadcast against {against} (the shape of {})",
                    tuple(s.shape.dims(), s.item),
                    from.join(" and ")
                ),
            });
        }
        if next.len() > MAX_BATCH_LEN {
            let n = next.dims().iter().try_fold(1u128, |a, &d| a.checked_mul(d as u128));
            let count = n.map_or_else(|| "more than 2^128".to_string(), |n| n.to_string());
            return Err(BrdfError::InvalidInput {
                name: s.name,
                problem: format!(
                    "broadcasting gives shape {}, {count} elements, which is too many: a batch holds at \
                     most {MAX_BATCH_LEN} (2^32, MAX_BATCH_LEN); split it into parts",
                    tuple(next.dims(), s.item)
                ),
            });
        }
        if next != out {
            from.push(s.name);
        }
        out = next;
    }
    Ok(out)
}

/// How element `i` of a batch of shape `out` finds its element in an input.
// One per input of a batch, never in arrays: the inline strides cost nothing and avoid an allocation.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
pub(crate) enum Layout {
    /// One element, used for every output element.
    Single,
    /// As many elements as the output, in the same order: element `i`.
    Full,
    /// Broadcast along some dimensions but not all: an odometer over the output's (collapsed)
    /// dimensions with stride 0 along the broadcast ones.
    Strided(Strides),
}

/// The output's dimensions (size-1 ones dropped) and the input's stride along each.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Strides {
    ndim: usize,
    dims: [usize; MAX_DIMS],
    strides: [usize; MAX_DIMS],
}

impl Layout {
    /// The layout of an input of shape `input` in a batch of shape `out` (which `input` broadcasts to).
    pub(crate) fn of(input: &Shape, out: &Shape) -> Layout {
        let (n_in, n_out) = (input.len(), out.len());
        if n_in == 1 {
            return Layout::Single;
        }
        if n_in == n_out {
            return Layout::Full;
        }
        let (a, b) = (input.dims(), out.dims());
        let pad = b.len() - a.len();
        let mut s = Strides { ndim: 0, dims: [1; MAX_DIMS], strides: [0; MAX_DIMS] };
        let mut stride = 1;
        // Input strides in C order, from the last dimension; 0 where the input has size 1.
        let mut per_dim = [0usize; MAX_DIMS];
        for k in (0..b.len()).rev() {
            let d_in = if k >= pad { a[k - pad] } else { 1 };
            per_dim[k] = if d_in == 1 { 0 } else { stride };
            stride *= d_in;
        }
        for k in 0..b.len() {
            if b[k] == 1 {
                continue;
            }
            // Merge with the previous kept dimension when the two walk memory as one.
            if s.ndim > 0 && s.strides[s.ndim - 1] == per_dim[k] * b[k] {
                s.dims[s.ndim - 1] *= b[k];
                s.strides[s.ndim - 1] = per_dim[k];
                continue;
            }
            s.dims[s.ndim] = b[k];
            s.strides[s.ndim] = per_dim[k];
            s.ndim += 1;
        }
        Layout::Strided(s)
    }

    /// The input index read by output element `i` (random access; sequential readers use
    /// [`Odometer`]).
    #[inline]
    pub(crate) fn index(&self, i: usize) -> usize {
        match self {
            Layout::Single => 0,
            Layout::Full => i,
            Layout::Strided(s) => Odometer::new(s, i).pos,
        }
    }
}

/// Walks the input indices of consecutive output elements of a [`Layout::Strided`] input.
#[derive(Debug, Clone)]
pub(crate) struct Odometer {
    s: Strides,
    idx: [usize; MAX_DIMS],
    pos: usize,
}

impl Odometer {
    /// Positioned at output element `start`.
    pub(crate) fn new(s: &Strides, mut start: usize) -> Self {
        let mut o = Odometer { s: *s, idx: [0; MAX_DIMS], pos: 0 };
        for k in (0..s.ndim).rev() {
            o.idx[k] = start % s.dims[k];
            start /= s.dims[k];
            o.pos += o.idx[k] * s.strides[k];
        }
        o
    }

    /// The current input index, then step to the next output element.
    #[inline(always)]
    pub(crate) fn next_index(&mut self) -> usize {
        let here = self.pos;
        let mut k = self.s.ndim;
        while k > 0 {
            k -= 1;
            self.idx[k] += 1;
            self.pos += self.s.strides[k];
            if self.idx[k] < self.s.dims[k] {
                break;
            }
            self.pos -= self.s.strides[k] * self.s.dims[k];
            self.idx[k] = 0;
        }
        here
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(d: &[usize]) -> Shape {
        Shape::new(d).unwrap()
    }

    fn bc(shapes: &[&[usize]]) -> Result<Shape, BrdfError> {
        const NAMES: [&str; 4] = ["l", "v", "n", "tangent"];
        let shapes: Vec<Shape> = shapes.iter().map(|d| shape(d)).collect();
        let of: Vec<ShapeOf<'_>> =
            shapes.iter().zip(NAMES).map(|(shape, name)| ShapeOf { name, shape, item: &[3] }).collect();
        broadcast(&of)
    }

    #[test]
    fn broadcasting_follows_numpy() {
        assert_eq!(bc(&[&[90, 360], &[], &[1]]).unwrap(), shape(&[90, 360]));
        assert_eq!(bc(&[&[90, 1], &[360]]).unwrap(), shape(&[90, 360]));
        assert_eq!(bc(&[&[5, 1, 4], &[3, 1]]).unwrap(), shape(&[5, 3, 4]));
        assert_eq!(bc(&[&[], &[]]).unwrap(), Shape::SCALAR);
        assert_eq!(bc(&[&[7], &[1], &[7]]).unwrap(), Shape::rows(7));
        let e = bc(&[&[5], &[4]]).unwrap_err().to_string();
        assert!(
            e.starts_with("v:") && e.contains("(4, 3)") && e.contains("(5, 3)") && e.contains("of l"),
            "{e}"
        );
        let e = bc(&[&[2, 5], &[1, 5], &[3, 1]]).unwrap_err().to_string();
        assert!(e.starts_with("n:") && e.contains("(3, 1, 3)") && e.contains("(2, 5, 3)"), "{e}");
        let huge = usize::MAX / 2;
        assert!(bc(&[&[huge, 1], &[1, huge]]).unwrap_err().to_string().contains("too many"));
    }

    /// A batch of up to MAX_BATCH_LEN elements is accepted; one more is refused (before any allocation),
    /// naming the input that took the shape past the limit and saying what the limit is.
    #[test]
    fn batches_beyond_max_batch_len_are_refused_naming_the_input() {
        assert_eq!(MAX_BATCH_LEN, 1 << 32);
        assert_eq!(bc(&[&[1 << 16, 1], &[1, 1 << 16]]).unwrap().len(), MAX_BATCH_LEN);
        let e = bc(&[&[(1 << 16) + 1, 1], &[1, 1 << 16]]).unwrap_err().to_string();
        assert!(e.starts_with("v:"), "{e}");
        assert!(e.contains("(65537, 65536, 3)") && e.contains("4295032832 elements"), "{e}");
        assert!(e.contains("4294967296") && e.contains("split"), "{e}");
        let e = bc(&[&[3], &[1 << 31, 1], &[1 << 31, 1, 1]]).unwrap_err().to_string();
        assert!(e.starts_with("v:"), "{e}");
    }

    /// Every layout reads, for each output element, the element NumPy's broadcasting would read.
    #[test]
    fn layouts_read_the_elements_numpy_reads() {
        let cases: [(&[usize], &[usize]); 7] = [
            (&[4, 5, 6], &[4, 5, 6]),
            (&[1], &[4, 5, 6]),
            (&[6], &[4, 5, 6]),
            (&[5, 1], &[4, 5, 6]),
            (&[4, 1, 6], &[4, 5, 6]),
            (&[4, 1, 1], &[4, 5, 6]),
            (&[1, 5, 6], &[4, 5, 6]),
        ];
        for (input, out) in cases {
            let (si, so) = (shape(input), shape(out));
            let layout = Layout::of(&si, &so);
            let pad = so.ndim() - si.ndim();
            let mut odo = match layout {
                Layout::Strided(s) => Some(Odometer::new(&s, 0)),
                _ => None,
            };
            for i in 0..so.len() {
                let idx = so.unravel(i);
                let want = (0..si.ndim()).fold(0, |acc, k| {
                    let d = si.dims()[k];
                    acc * d + if d == 1 { 0 } else { idx[k + pad] }
                });
                assert_eq!(layout.index(i), want, "{input:?} in {out:?} at {idx:?}");
                if let Some(o) = odo.as_mut() {
                    assert_eq!(o.next_index(), want, "{input:?} in {out:?} at {idx:?}");
                }
            }
        }
    }

    #[test]
    fn shapes_print_as_python_tuples() {
        assert_eq!(tuple(&[], &[3]), "(3,)");
        assert_eq!(tuple(&[5], &[3]), "(5, 3)");
        assert_eq!(tuple(&[], &[]), "()");
        assert_eq!(format!("{:?}", shape(&[2, 7])), "(2, 7)");
        assert_eq!(shape(&[2, 3, 4]).unravel(23), vec![1, 2, 3]);
    }
}
