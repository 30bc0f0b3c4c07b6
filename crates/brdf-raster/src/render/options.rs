//! [`RenderOptions`]: image size, shading, supersampling, tone mapping, obscurance and shadows, and the
//! limits a render checks them against.

use brdf_core::tonemap::Operator;

use crate::RasterError;
use crate::ao::AoOptions;
use crate::area_lighting::AreaSampling;
use crate::environment::EnvironmentMode;
use crate::shading::ShadingMode;

/// Largest accepted image width or height in pixels.
pub const MAX_IMAGE_SIDE: u32 = 16384;
/// Largest accepted image, `width · height` pixels (2^26: e.g. 8192 × 8192, or 4K UHD eight times over),
/// **whatever the number of samples per pixel**. This is the one place the limit is stated: the Python
/// `Scene.render` docs and its error message read it from here (`raster_limits()`).
///
/// Why that size: the frame holds at most 35 bytes per pixel (HDR colour 12, depth 4, normal 12,
/// triangle id 4, 8-bit sRGB 3, each only if asked for, see [`Outputs`]), about 2.3 GB at the limit.
/// Supersampled samples never exist for the whole image: each band of [`crate::tiles::band_rows`] image
/// rows is drawn at `s × s` samples per pixel into per-thread scratch of about 16 sample rows (36 bytes
/// per sample, `16 · width · s · 36` bytes: 8.8 MB for a 3840-pixel-wide image at 16 samples per
/// pixel) and resolved into the frame at once, so memory grows with `s`, not with `s²` or the height.
pub const MAX_PIXELS: u64 = 1 << 26;

/// Which buffers a render writes into its [`crate::Frame`]; the others stay empty (length 0, their
/// allocation kept for a later render that asks for them). Writing only what is read saves memory
/// traffic: at 1080p the HDR, normal and triangle-id buffers are 58 MB a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Outputs(u8);

impl Outputs {
    /// Nothing (not a valid render request by itself).
    pub const NONE: Self = Self(0);
    /// The 8-bit sRGB image ([`crate::Frame::rgb8`]), encoded band by band during the render with the
    /// render's tone map and exposure — cheaper than [`crate::Frame::to_rgb8`] afterwards, which reads
    /// the whole HDR buffer again.
    pub const RGB8: Self = Self(1);
    /// Linear HDR colour ([`crate::Frame::hdr`]).
    pub const HDR: Self = Self(2);
    /// Window depth ([`crate::Frame::depth`]).
    pub const DEPTH: Self = Self(4);
    /// World-space shading normal ([`crate::Frame::normal`]).
    pub const NORMAL: Self = Self(8);
    /// Face index ([`crate::Frame::triangle_id`]).
    pub const TRIANGLE_ID: Self = Self(16);
    /// HDR colour, depth, normal and triangle id: what [`RenderOptions::new`] asks for.
    pub const BUFFERS: Self = Self(2 | 4 | 8 | 16);
    /// Every output.
    pub const ALL: Self = Self(31);
    /// The outputs by name, as the Python API spells them.
    pub const NAMES: [(&'static str, Outputs); 5] = [
        ("rgb", Self::RGB8),
        ("hdr", Self::HDR),
        ("depth", Self::DEPTH),
        ("normal", Self::NORMAL),
        ("triangle_id", Self::TRIANGLE_ID),
    ];

    /// Whether every output of `other` is in `self`.
    #[inline]
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// Whether nothing is asked for.
    #[inline]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The outputs named (see [`Outputs::NAMES`]); an unknown name is an error naming `outputs`.
    pub fn from_names<'a>(names: impl IntoIterator<Item = &'a str>) -> Result<Self, RasterError> {
        let mut o = Self::NONE;
        for name in names {
            let Some(&(_, x)) = Self::NAMES.iter().find(|(n, _)| *n == name) else {
                let known: Vec<&str> = Self::NAMES.iter().map(|(n, _)| *n).collect();
                return Err(RasterError::arg(
                    "outputs",
                    format!("unknown output {name:?}; expected some of {}", known.join(", ")),
                ));
            };
            o = o | x;
        }
        Ok(o)
    }

    /// The names of the outputs in `self`, in [`Outputs::NAMES`] order.
    pub fn names(self) -> Vec<&'static str> {
        Self::NAMES.iter().filter(|(_, x)| self.contains(*x)).map(|(n, _)| *n).collect()
    }
}

impl std::ops::BitOr for Outputs {
    type Output = Self;
    #[inline]
    fn bitor(self, o: Self) -> Self {
        Self(self.0 | o.0)
    }
}

/// How to render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels, 1..=[`MAX_IMAGE_SIDE`].
    pub width: u32,
    /// Image height in pixels, 1..=[`MAX_IMAGE_SIDE`].
    pub height: u32,
    /// Shading algorithm (Theoharis et al. 2008, ch. 12).
    pub shading: ShadingMode,
    /// Skip triangles whose back (clockwise side) faces the camera.
    pub cull_back_faces: bool,
    /// Supersampling: 1, 4, 9 or 16 samples per pixel on a regular `s × s` grid (`s² = samples`),
    /// resolved by a box filter.
    pub samples_per_pixel: u32,
    /// Tone-mapping operator of [`Frame::to_rgb8`](crate::Frame::to_rgb8).
    pub tonemap: Operator,
    /// Exposure in stops of [`Frame::to_rgb8`](crate::Frame::to_rgb8).
    pub exposure: f32,
    /// Ambient obscurance (Theoharis et al. 2008 eq. 12.72) weighting the ambient term, per vertex or per
    /// pixel;
    /// `None`: off. Used by [`render`](super::render) (see [`crate::occlusion::SceneOcclusion`]).
    pub ao: Option<AoOptions>,
    /// Light visibility δ by shadow rays (Theoharis et al. 2008 eq. 12.75). Used by
    /// [`render`](super::render).
    pub shadows: bool,
    /// The buffers to write (the others are left empty).
    pub outputs: Outputs,
    /// How the scene's environment (if it has one) lights it ([`crate::environment`]).
    pub environment: EnvironmentMode,
    /// Samples and seed of the scene's area lights, if it has any ([`crate::area_lighting`]).
    pub area: AreaSampling,
}

impl RenderOptions {
    /// `width × height`, Phong shading, back faces culled, one sample per pixel, clamp, exposure 0.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            shading: ShadingMode::Phong,
            cull_back_faces: true,
            samples_per_pixel: 1,
            tonemap: Operator::Clamp,
            exposure: 0.0,
            ao: None,
            shadows: false,
            outputs: Outputs::BUFFERS,
            environment: EnvironmentMode::Fast,
            area: AreaSampling::default(),
        }
    }

    /// The supersampling factor per axis `s` (`samples_per_pixel = s²`).
    pub fn ssaa_factor(&self) -> u32 {
        match self.samples_per_pixel {
            4 => 2,
            9 => 3,
            16 => 4,
            _ => 1,
        }
    }

    /// Check the image size against the documented limits and the other options.
    pub fn validate(&self) -> Result<(), RasterError> {
        for (name, v) in [("width", self.width), ("height", self.height)] {
            if v == 0 || v > MAX_IMAGE_SIDE {
                return Err(RasterError::arg(
                    name,
                    format!("must be in 1..={MAX_IMAGE_SIDE} pixels, got {v}"),
                ));
            }
        }
        if ![1, 4, 9, 16].contains(&self.samples_per_pixel) {
            return Err(RasterError::arg(
                "samples_per_pixel",
                format!("must be 1, 4, 9 or 16 (an s×s grid), got {}", self.samples_per_pixel),
            ));
        }
        let pixels = u64::from(self.width) * u64::from(self.height);
        if pixels > MAX_PIXELS {
            return Err(RasterError::arg(
                "width, height",
                format!(
                    "{}×{} = {pixels} pixels exceeds the limit of {MAX_PIXELS} pixels (2^26, at any number \
                     of samples per pixel)",
                    self.width, self.height
                ),
            ));
        }
        if self.outputs.is_empty() {
            return Err(RasterError::arg("outputs", "asks for no output; name at least one"));
        }
        if !self.exposure.is_finite() {
            return Err(RasterError::arg("exposure", format!("must be finite, got {}", self.exposure)));
        }
        if let Some(ao) = &self.ao {
            ao.validate()?;
        }
        self.area.validate()?;
        self.environment.validate()
    }
}
