//! What kinds of lobes a BSDF has, or a caller asks for (pbrt-v4's `BxDFFlags` and sample flags,
//! Mitsuba's `BSDFContext`).

use std::ops::{BitAnd, BitOr};

/// Reflection and/or transmission, each diffuse, glossy or delta (a perfect mirror or
/// refraction, which no light sample can meet). As a mask a caller passes to `Bsdf::sample`
/// and `Bsdf::pdf`, its diffuse, glossy and delta bits choose the lobes taken part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LobeFlags(u8);

impl LobeFlags {
    pub const NONE: Self = LobeFlags(0);
    pub const REFLECTION: Self = LobeFlags(1);
    pub const TRANSMISSION: Self = LobeFlags(2);
    pub const DIFFUSE: Self = LobeFlags(4);
    pub const GLOSSY: Self = LobeFlags(8);
    pub const DELTA: Self = LobeFlags(16);
    /// The lobes with a density, which next-event estimation and MIS reach.
    pub const NON_DELTA: Self = LobeFlags(4 | 8);
    /// Every lobe.
    pub const ALL: Self = LobeFlags(31);

    /// Both sets of flags (`|` in constants).
    #[inline]
    pub const fn union(self, other: Self) -> Self {
        LobeFlags(self.0 | other.0)
    }

    /// These flags but those of `other`.
    #[inline]
    pub fn without(self, other: Self) -> Self {
        LobeFlags(self.0 & !other.0)
    }

    /// Whether no flag is set.
    #[inline]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Whether every flag of `other` is set.
    #[inline]
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// Whether some flag of `other` is set.
    #[inline]
    pub fn intersects(self, other: Self) -> bool {
        self.0 & other.0 != 0
    }

    /// Whether a lobe of these flags takes part under `mask`: one of its kinds (diffuse,
    /// glossy, delta) is asked for.
    #[inline]
    pub fn is_in(self, mask: Self) -> bool {
        self.intersects(mask & (LobeFlags::DIFFUSE | LobeFlags::GLOSSY | LobeFlags::DELTA))
    }

    /// Whether some lobe has a density: next-event estimation and MIS apply there.
    #[inline]
    pub fn is_non_delta(self) -> bool {
        self.intersects(LobeFlags::NON_DELTA)
    }

    #[inline]
    pub fn is_delta(self) -> bool {
        self.contains(LobeFlags::DELTA)
    }

    /// Whether `Bsdf::sample` over every lobe reads its `u_lobe`: there are lobes besides a
    /// diffuse one (a choice between lobes, or within one: reflection or refraction).
    #[inline]
    pub fn chooses_lobe(self) -> bool {
        self.intersects(LobeFlags::DELTA | LobeFlags::GLOSSY)
    }
}

impl BitOr for LobeFlags {
    type Output = Self;
    #[inline]
    fn bitor(self, rhs: Self) -> Self {
        LobeFlags(self.0 | rhs.0)
    }
}

impl BitAnd for LobeFlags {
    type Output = Self;
    #[inline]
    fn bitand(self, rhs: Self) -> Self {
        LobeFlags(self.0 & rhs.0)
    }
}
