//! Generated environments, so nothing is downloaded: `studio`, `sky` and `white`.

use glam::DVec3;

use super::EnvMap;

/// A built-in environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Builtin {
    /// Soft rectangular lights over a dim gradient: the look-dev studio.
    Studio,
    /// An analytic daylight sky with a sun.
    Sky,
    /// Uniform radiance 1, taken through the map path (the furnace of the whole path).
    White,
}

/// The width a built-in is generated at unless asked otherwise (height is half).
pub const DEFAULT_BUILTIN_WIDTH: u32 = 1024;

impl Builtin {
    /// Every built-in, in the order the help lists them.
    pub const ALL: [Builtin; 3] = [Builtin::Studio, Builtin::Sky, Builtin::White];

    /// The name the command line and the scene file use.
    pub fn name(self) -> &'static str {
        match self {
            Builtin::Studio => "studio",
            Builtin::Sky => "sky",
            Builtin::White => "white",
        }
    }

    /// The map, `width x width / 2` texels (`width` even, at least 2).
    pub fn generate(self, width: u32) -> EnvMap {
        let width = width.max(2) & !1;
        match self {
            // TODO(helper): studio and sky.
            Builtin::Studio | Builtin::Sky | Builtin::White => {
                EnvMap::uniform(DVec3::ONE, width, width / 2)
            }
        }
    }
}

crate::named_enum!(Builtin, "built-in environment");
