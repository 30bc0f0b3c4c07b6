//! Alpha testing in the coverage pass (glTF 2.0 `alphaMode` `MASK`, §3.9.4): a sample of a masked
//! instance whose mask value is below the cutoff is discarded before the depth test writes it, so it
//! neither shows nor hides what lies behind — the cut-out leaves of a foliage card.
//!
//! The mask is read as shading reads textures: at the sample's perspective-correct texture
//! coordinates with their screen derivatives (the mip level, [`BaryPlanes::at_with_derivatives`]), so
//! a minified mask fades by its mip chain rather than aliasing. Only samples that pass the depth test
//! read the mask. Each sample is a pure function of its position and the scene: the frame stays
//! bit-identical at any thread count. Shadow and ambient-occlusion rays still see whole triangles.

use glam::Vec2;

use super::interpolate::BaryPlanes;
use super::vertex::Prepared;
use crate::texture::AlphaMask;
use crate::tiles::{DepthTest, Fragments, TriRef, split_ref};

/// The triangle last tested: its barycentric planes and texture coordinates (fragments arrive
/// triangle by triangle).
struct Cached {
    tri: TriRef,
    bary: BaryPlanes,
    uv: [Vec2; 3],
}

/// [`DepthTest`] behind an alpha test of the masked instances.
pub(super) struct AlphaTested<'p, 'b> {
    pub(super) prep: &'p Prepared<'p>,
    pub(super) depth: DepthTest<'b>,
    /// The band's first sample row and its width in samples.
    pub(super) row0: i32,
    pub(super) width: usize,
    cached: Option<Cached>,
}

impl<'p, 'b> AlphaTested<'p, 'b> {
    /// Over `prep.masks` (one per instance).
    pub(super) fn new(prep: &'p Prepared<'p>, depth: DepthTest<'b>, row0: i32, width: usize) -> Self {
        Self { prep, depth, row0, width, cached: None }
    }

    /// Whether triangle `tri`'s sample `index` passes the alpha test of `mask`.
    #[inline]
    fn passes(&mut self, mask: &AlphaMask, index: usize, tri: TriRef) -> bool {
        let prep = self.prep;
        let (ci, local) = split_ref(tri);
        let chunk = &prep.chunks[ci];
        if self.cached.as_ref().is_none_or(|c| c.tri != tri) {
            let k = chunk.instance as usize;
            let (data, mesh) = (&prep.instances[k], &prep.scene.instances[k].mesh);
            let t = &chunk.raster[local];
            let idx = mesh.indices[chunk.interp[local].face as usize];
            let p = idx.map(|j| prep.world[data.vertex_base + j as usize].p);
            // The scene's validation guarantees texture coordinates on a masked mesh.
            let uv = idx.map(|j| mesh.uvs.as_deref().map_or(Vec2::ZERO, |u| u[j as usize]));
            self.cached = Some(Cached { tri, bary: BaryPlanes::new(&prep.rays, p, t.min_x, t.min_y), uv });
        }
        let Some(c) = self.cached.as_ref() else { return true };
        let (col, row) = ((index % self.width) as i32, self.row0 + (index / self.width) as i32);
        let (b, db_dc, db_dr) = c.bary.at_with_derivatives(col, row);
        let at = |w: glam::Vec3| c.uv[0] * w.x + c.uv[1] * w.y + c.uv[2] * w.z;
        mask.passes(at(b), at(db_dc), at(db_dr))
    }
}

impl Fragments for AlphaTested<'_, '_> {
    #[inline(always)]
    fn fragment(&mut self, index: usize, z: f32, tri: TriRef) {
        if z >= self.depth.depth[index] {
            return;
        }
        let (ci, _) = split_ref(tri);
        if let Some(mask) = self.prep.masks[self.prep.chunks[ci].instance as usize] {
            if !self.passes(mask, index, tri) {
                return;
            }
        }
        self.depth.fragment(index, z, tri);
    }
}
