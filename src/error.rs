//! The library's error type.

use std::path::PathBuf;

/// Everything the library can report instead of panicking.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A name (scene, material, form, ...) that is not one of the allowed values.
    #[error("unknown {what} '{given}'; allowed: {}", allowed.join(", "))]
    UnknownName {
        /// What kind of name it is ("scene", "material", ...).
        what: &'static str,
        /// The name given.
        given: String,
        /// The allowed names.
        allowed: Vec<&'static str>,
    },
    /// A parameter outside its meaningful range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as the user sees it.
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// What the value must satisfy.
        reason: &'static str,
    },
    /// A mesh that cannot be simulated (degenerate or inconsistent).
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
    /// No GPU adapter could be opened.
    #[error(
        "no GPU adapter found ({0}). On a machine without a GPU install Mesa's Vulkan driver \
         (Debian/Ubuntu: `sudo apt-get install mesa-vulkan-drivers libvulkan1`); simulating alone \
         also works on the CPU backend (`simulate --backend cpu`)"
    )]
    NoAdapter(String),
    /// No window could be opened (no display, or the windowing system refused).
    #[error(
        "cannot open a window ({0}). The viewer needs a display (X11, or Wayland through XWayland; \
         on a machine without one run it under `xvfb-run -a`). Without a window, `eapbd render` \
         writes PNG frames and `eapbd simulate` prints per-frame statistics"
    )]
    NoDisplay(String),
    /// A GPU operation failed.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// The browser refused what the web page asked of it (wasm32 only).
    #[error("in the web page: {0}")]
    Web(String),
    /// A feature that this backend or build does not provide yet.
    #[error("not supported: {0}")]
    Unsupported(String),
    /// A report could not be produced.
    #[error("report: {0}")]
    Report(String),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

/// The library's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    pub fn param(name: &'static str, value: impl std::fmt::Display, reason: &'static str) -> Self {
        Error::InvalidParameter { name, value: value.to_string(), reason }
    }

    /// Looks `given` up among `(name, value)` pairs, or reports the allowed names.
    pub fn lookup<T: Copy>(what: &'static str, given: &str, table: &[(&'static str, T)]) -> Result<T> {
        table.iter().find(|(n, _)| *n == given).map(|(_, v)| *v).ok_or_else(|| Error::UnknownName {
            what,
            given: given.to_string(),
            allowed: table.iter().map(|(n, _)| *n).collect(),
        })
    }
}

/// The command-line names of a fieldless enum, declared once: `NAMES` (accepted names),
/// `name()` (a value's name) and `FromStr` through [`Error::lookup`] (an unknown name is an
/// error naming `what` and the accepted names); `also` adds names accepted besides.
macro_rules! command_names {
    ($ty:ident, $what:literal, { $($variant:ident => $name:literal),+ $(,)? }
        $(also { $($alias:literal => $aliased:ident),+ $(,)? })?) => {
        impl $ty {
            /// Names accepted on the command line.
            pub const NAMES: [&'static str; [$($name),+].len()] = [$($name),+];

            /// The command-line name.
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }
        }

        impl std::str::FromStr for $ty {
            type Err = $crate::error::Error;
            fn from_str(s: &str) -> $crate::error::Result<Self> {
                $crate::error::Error::lookup($what, s, &[$(($name, $ty::$variant)),+ $($(, ($alias, $ty::$aliased))+)?])
            }
        }
    };
}
pub(crate) use command_names;
