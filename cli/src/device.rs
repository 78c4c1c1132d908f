//! The device a command computes on, chosen one way for every command:
//! `--device` (else `PIXGEO_DEVICE`), with the machine timed by the tool's
//! profiler.

use anyhow::{Context, Result};
use pixgeo::machine::{DeviceChoice, Machine, MachineOptions};

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

impl Backend {
    /// `--device cpu` (or PIXGEO_DEVICE=cpu) asks for the CPU algorithms; any other
    /// choice is a Vulkan device. Without a Vulkan driver the CPU algorithms step
    /// in, with a notice.
    pub fn choose(device: Option<&str>) -> Result<Self> {
        let wanted = device
            .map(str::to_string)
            .or_else(|| std::env::var("PIXGEO_DEVICE").ok());
        if wanted
            .as_deref()
            .is_some_and(|w| w.trim().eq_ignore_ascii_case("cpu"))
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
