//! The device a command computes on, chosen one way for every command:
//! `--device` (else `PIXGEO_DEVICE`), with the machine timed by the tool's
//! profiler.

use std::sync::Mutex;

use anyhow::{Context, Result};
pub use pixgeo::Backend;
use pixgeo::{
    machine::{DeviceChoice, Machine, MachineOptions},
    Chosen, Need,
};

/// Work asked of a route that only a Vulkan device draws: an option of the
/// cones, say, where the CPU computes.
#[derive(Debug)]
pub struct DrawnOnly(pub String);

impl std::fmt::Display for DrawnOnly {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for DrawnOnly {}

/// Whether `error` says its work needs a Vulkan device this run has not: no
/// driver, no such device, or a drawing asked of the CPU.
pub fn needs_a_device(error: &anyhow::Error) -> bool {
    error.chain().any(|e| {
        e.is::<DrawnOnly>()
            || matches!(
                e.downcast_ref::<pixgeo::Error>(),
                Some(
                    pixgeo::Error::NoVulkan(_)
                        | pixgeo::Error::NoDevice(_)
                        | pixgeo::Error::Unsupported(_)
                )
            )
    })
}

/// The machine's options for `device` (else as PIXGEO_DEVICE says).
fn options(device: Option<&str>) -> MachineOptions {
    let mut options = MachineOptions::from_env().profiler(Some(crate::profiler().clone()));
    if let Some(d) = device {
        options.device = DeviceChoice::parse(d);
    }
    options
}

/// The pixel machine on `device` (else as PIXGEO_DEVICE says).
pub fn machine_on(device: Option<&str>) -> Result<Machine> {
    Machine::new(&options(device)).context("starting the pixel machine")
}

/// `--device` of the commands that need a Vulkan device.
#[derive(clap::Args)]
pub struct VulkanDevice {
    /// Vulkan device: auto, lavapipe, gpu, an index, or part of a name (default:
    /// PIXGEO_DEVICE); this command has no CPU algorithm, so `cpu` is refused.
    #[arg(long = "device")]
    pub name: Option<String>,
}

impl VulkanDevice {
    /// The pixel machine on this device.
    pub fn machine(&self) -> Result<Machine> {
        machine_on(self.name.as_deref())
    }
}

/// `--device` of the commands with an exact CPU algorithm.
#[derive(clap::Args)]
pub struct DeviceArg {
    /// Where to compute: auto, cpu, lavapipe, gpu, an index, or part of a
    /// device name (default: PIXGEO_DEVICE). Every choice gives the same
    /// answer; without a Vulkan driver, auto computes on the CPU, with a note.
    #[arg(long = "device")]
    pub name: Option<String>,
}

impl DeviceArg {
    /// Where the work runs ([`choose`]).
    pub fn choose(&self, need: Need) -> Result<Chosen> {
        choose(self.name.as_deref(), need)
    }
}

/// Why the CPU computed where a device was asked for, once announced: the
/// `fallback` of the `--json` envelope.
static FALLBACK: Mutex<Option<String>> = Mutex::new(None);

/// The fallback this run announced, if any.
pub fn fallback() -> Option<String> {
    FALLBACK.lock().ok().and_then(|f| f.clone())
}

/// Where the work runs, by the core's one rule ([`Backend::choose`]) from
/// `--device` (else `PIXGEO_DEVICE`); a fallback to the CPU is announced on
/// stderr and in the `--json` envelope.
pub fn choose(device: Option<&str>, need: Need) -> Result<Chosen> {
    let chosen = Backend::choose(&options(device), need).context("starting the pixel machine")?;
    if let Some(why) = &chosen.fallback {
        note!("note: {why}");
        if let Ok(mut slot) = FALLBACK.lock() {
            *slot = Some(why.clone());
        }
    }
    Ok(chosen)
}

/// The need of work with an exact CPU algorithm: pictures the CPU draws
/// faster than a software rasterizer are `small`.
pub fn need(small: bool) -> Need {
    if small {
        Need::CpuUnlessGpu
    } else {
        Need::DeviceIfAny
    }
}

/// Pictures up to this many pixels are drawn faster by the CPU pixel
/// algorithms than by a software rasterizer, whose start alone (loading its
/// compiler) outweighs them (`docs/benchmarks.md` has the measurements).
pub const CPU_FASTER_PIXELS: u64 = 512 * 512;
