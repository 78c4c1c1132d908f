//! The library's error type.

use std::path::PathBuf;

/// Everything a pixgeo call can fail with. New kinds of failure may be added,
/// so a `match` needs a `_` arm.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The Vulkan loader or a driver is missing.
    #[error("no Vulkan driver: {0}. Install a Vulkan loader and driver: libvulkan1 and mesa-vulkan-drivers on Debian and Ubuntu, vulkan-loader and mesa-vulkan-drivers on Fedora and RHEL")]
    NoVulkan(String),
    /// No device matched the request (`PIXGEO_DEVICE`) or none has what pixgeo needs.
    #[error("no suitable Vulkan device: {0}")]
    NoDevice(String),
    /// A Vulkan call failed: `code` is its `VkResult`, `name` that code's name.
    #[error("Vulkan call {call} failed: {name}")]
    Vulkan {
        call: &'static str,
        code: i32,
        name: String,
    },
    /// The Khronos validation layer reported problems (only with `PIXGEO_VALIDATION=1`).
    #[error("Vulkan validation reported {} message(s):\n{}", .0.len(), .0.join("\n"))]
    Validation(Vec<String>),
    /// Device memory could not be allocated (the allocator's message).
    #[error("device memory: {0}")]
    Memory(String),
    /// The input is not something pixgeo can compute with: why, by kind.
    #[error("invalid input: {0}")]
    InvalidInput(Invalid),
    /// The picture (or one image of the device) is larger than allowed.
    #[error("picture {width}x{height} is too large: sides of at most {limit} pixels")]
    PictureTooLarge { width: u32, height: u32, limit: u32 },
    /// A file could not be read or written. The OS error is in the message,
    /// not a separate source, so that a chain of causes names it once.
    #[error("{path}: {cause}")]
    Io {
        path: PathBuf,
        cause: std::io::Error,
    },
    /// A file was read but its content is malformed.
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    /// The device lacks a feature the computation needs (float64 shaders,
    /// 64-bit atomics, logic operations).
    #[error("the device does not support {0}")]
    Unsupported(String),
    /// pixgeo broke one of its own invariants: a bug, not the input's fault.
    #[error("{0}; this is a pixgeo bug, please report it with the input")]
    Internal(String),
    /// A [`Machine`](crate::Machine) was used against its rules: an image or
    /// buffer of another machine, or a run started inside a run.
    #[error("machine misuse: {0}")]
    Usage(String),
    /// The work would hold more host memory than this process can have.
    #[error("{what}: needs about {} of memory, more than this process can have", crate::memory::amount(*.bytes))]
    HostMemory { what: String, bytes: u64 },
    /// The call was cancelled through [`Machine::cancel_flag`](crate::Machine::cancel_flag).
    #[error("cancelled")]
    Cancelled,
}

impl Error {
    /// The failure of the Vulkan call `call`.
    pub(crate) fn vulkan(call: &'static str, result: ash::vk::Result) -> Self {
        Self::Vulkan {
            call,
            code: result.as_raw(),
            name: result.to_string(),
        }
    }

    /// A failure of the device memory allocator.
    pub(crate) fn memory(error: gpu_allocator::AllocationError) -> Self {
        Self::Memory(error.to_string())
    }

    /// A failure to allocate `bytes` of device memory for `what`.
    pub(crate) fn memory_for(
        error: gpu_allocator::AllocationError,
        what: &str,
        bytes: u64,
    ) -> Self {
        Self::Memory(format!(
            "{what} ({}): {error}; use a smaller picture, or smaller tiles (max_tile, --max-tile)",
            crate::memory::amount(bytes)
        ))
    }

    /// Names what an invalid input was (`first set: site 3 ...`), once.
    pub(crate) fn about(self, what: &str) -> Self {
        match self {
            Self::InvalidInput(why) => Self::InvalidInput(why.about(what)),
            other => other,
        }
    }

    /// A value that is NaN or infinite, at `index` of its list if it has one.
    pub fn not_finite(index: Option<usize>, message: String) -> Self {
        Self::InvalidInput(Invalid::NotFinite { index, message })
    }

    /// Fewer items than the work needs.
    pub fn too_few(needed: usize, given: usize, message: String) -> Self {
        Self::InvalidInput(Invalid::TooFew {
            needed,
            given,
            message,
        })
    }

    /// Input in a position with no answer ([`Invalid::Degenerate`]).
    pub fn degenerate(message: String) -> Self {
        Self::InvalidInput(Invalid::Degenerate(message))
    }

    /// A number or size beyond what works ([`Invalid::OutOfRange`]).
    pub fn out_of_range(message: String) -> Self {
        Self::InvalidInput(Invalid::OutOfRange(message))
    }

    /// An option this work does not take ([`Invalid::UnsupportedOption`]).
    pub fn unsupported_option(message: String) -> Self {
        Self::InvalidInput(Invalid::UnsupportedOption(message))
    }

    /// Input that contradicts itself ([`Invalid::Malformed`]).
    pub fn malformed(message: String) -> Self {
        Self::InvalidInput(Invalid::Malformed(message))
    }
}

/// Why pixgeo refused an input ([`Error::InvalidInput`]): the kind, for a
/// program to act on, and a message that says what works, for a person.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Invalid {
    /// A value that is NaN or infinite; `index` is its place in its list
    /// (a site, a value, a query point), where it has one.
    #[error("{message}")]
    NotFinite {
        index: Option<usize>,
        message: String,
    },
    /// Fewer items than the work needs: no sites, two points for a triangle.
    #[error("{message}")]
    TooFew {
        needed: usize,
        given: usize,
        message: String,
    },
    /// Input in a position with no answer: all on one line, one point, a
    /// region without a pixel centre.
    #[error("{0}")]
    Degenerate(String),
    /// A number or size beyond what pixgeo, or this device, computes with;
    /// the message names the range that works.
    #[error("{0}")]
    OutOfRange(String),
    /// An option, or a combination of options, that this problem or route
    /// does not take.
    #[error("{0}")]
    UnsupportedOption(String),
    /// Input that contradicts itself or its description: lengths that
    /// differ, repeated or misplaced items, a malformed box, an unknown name.
    #[error("{0}")]
    Malformed(String),
}

impl Invalid {
    /// The kind's name as the command line's JSON and Python give it:
    /// `not_finite`, `too_few`, `degenerate`, `out_of_range`,
    /// `unsupported_option` or `malformed`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::NotFinite { .. } => "not_finite",
            Self::TooFew { .. } => "too_few",
            Self::Degenerate(_) => "degenerate",
            Self::OutOfRange(_) => "out_of_range",
            Self::UnsupportedOption(_) => "unsupported_option",
            Self::Malformed(_) => "malformed",
        }
    }

    /// The numbers the kind carries, by name: `index` for `NotFinite`,
    /// `needed` and `given` for `TooFew`, none for the others.
    pub fn numbers(&self) -> Vec<(&'static str, Option<usize>)> {
        match *self {
            Self::NotFinite { index, .. } => Vec::from([("index", index)]),
            Self::TooFew { needed, given, .. } => {
                Vec::from([("needed", Some(needed)), ("given", Some(given))])
            }
            _ => Vec::new(),
        }
    }

    /// The message, prefixed by what the input was.
    fn about(self, what: &str) -> Self {
        let named = |message: String| format!("{what}: {message}");
        match self {
            Self::NotFinite { index, message } => Self::NotFinite {
                index,
                message: named(message),
            },
            Self::TooFew {
                needed,
                given,
                message,
            } => Self::TooFew {
                needed,
                given,
                message: named(message),
            },
            Self::Degenerate(m) => Self::Degenerate(named(m)),
            Self::OutOfRange(m) => Self::OutOfRange(named(m)),
            Self::UnsupportedOption(m) => Self::UnsupportedOption(named(m)),
            Self::Malformed(m) => Self::Malformed(named(m)),
        }
    }
}

/// Result with pixgeo's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Attaches the name of the failing Vulkan call to a `VkResult`.
pub(crate) trait VkContext<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for ash::prelude::VkResult<T> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::vulkan(call, result))
    }
}
