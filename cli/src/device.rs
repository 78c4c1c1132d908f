//! The device a command computes on, chosen one way for every command:
//! `--device` (else `PIXGEO_DEVICE`), with the machine timed by the tool's
//! profiler.

use anyhow::{Context, Result};
use pixgeo::machine::{has_gpu, DeviceChoice, Machine, MachineOptions};

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

/// Where diagrams are computed.
pub enum Backend {
    /// The pixel machine on a Vulkan device.
    Gpu(Box<Machine>),
    /// The thesis's CPU pixel algorithms (§3.12): no Vulkan needed.
    Cpu,
}

/// Pictures up to this many pixels are drawn faster by the CPU pixel
/// algorithms than by a software rasterizer, whose start alone (loading its
/// compiler) outweighs them (`docs/benchmarks.md` has the measurements).
pub const CPU_FASTER_PIXELS: u64 = 512 * 512;

impl Backend {
    /// `--device cpu` (or PIXGEO_DEVICE=cpu) asks for the CPU algorithms; any other
    /// choice is a Vulkan device. Without a choice, `small` work (a picture the
    /// CPU algorithms draw faster than a software rasterizer, giving the same
    /// answer) on a machine with no GPU takes the CPU algorithms. Without a
    /// Vulkan driver the CPU algorithms step in, with a notice.
    pub fn choose(device: Option<&str>, small: bool) -> Result<Self> {
        let wanted = device
            .map(str::to_string)
            .or_else(|| std::env::var("PIXGEO_DEVICE").ok());
        let auto = wanted
            .as_deref()
            .is_none_or(|w| w.trim().is_empty() || w.trim().eq_ignore_ascii_case("auto"));
        if wanted
            .as_deref()
            .is_some_and(|w| w.trim().eq_ignore_ascii_case("cpu"))
            || (auto && small && !has_gpu())
        {
            return Ok(Self::Cpu);
        }
        match Machine::new(&options(device)) {
            Ok(machine) => Ok(Self::Gpu(Box::new(machine))),
            Err(pixgeo::Error::NoVulkan(why)) => {
                note!("note: no Vulkan driver ({why}); using the CPU pixel algorithms");
                Ok(Self::Cpu)
            }
            Err(e) => Err(e).context("starting the pixel machine"),
        }
    }

    pub fn name(&self) -> &str {
        match self {
            Self::Gpu(machine) => machine.device_name(),
            Self::Cpu => "cpu (thesis §3.12 pixel algorithms)",
        }
    }
}
