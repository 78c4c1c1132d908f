//! Where a problem runs: the pixel machine on a Vulkan device, or the CPU
//! alone. One function, [`Backend::choose`], makes the choice for the command
//! line, Python, C and [`crate::with_default_backend`] alike, from the user's choice and
//! what the work needs; every answer called exact is the same on both.

use crate::{
    error::{Error, Result},
    machine::{has_gpu, DeviceChoice, Machine, MachineOptions},
};

/// Where work runs: a plain value, borrowed from whoever owns the machine.
#[derive(Clone, Copy)]
pub enum Backend<'m> {
    /// The pixel machine on a Vulkan device.
    Device(&'m Machine),
    /// The CPU alone: no Vulkan loader or driver is needed.
    Cpu,
}

/// What the work needs of a device, as [`Backend::choose`] reads it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Need {
    /// An exact CPU algorithm faster than a software rasterizer: the CPU
    /// unless a GPU is there.
    CpuUnlessGpu,
    /// An exact CPU algorithm that a device (lavapipe included) runs faster:
    /// the device when one starts, else the CPU, with a notice.
    DeviceIfAny,
    /// A drawing with no CPU algorithm (fans, peeling, flooding, the
    /// thesis's roofs), named here for the refusal without a device.
    Drawing(&'static str),
}

/// A chosen backend, owning its machine, and why it is not the one asked
/// for where it is not.
pub struct Chosen {
    /// The device's machine; `None`: the CPU.
    pub machine: Option<Machine>,
    /// Set when the CPU steps in because no Vulkan device starts: the reason,
    /// for the front end to announce (stderr, `--json`, a warning).
    pub fallback: Option<String>,
}

impl Chosen {
    /// Where the work runs.
    pub fn backend(&self) -> Backend<'_> {
        match &self.machine {
            Some(machine) => Backend::Device(machine),
            None => Backend::Cpu,
        }
    }
}

impl<'m> Backend<'m> {
    /// The one rule: `cpu` asks for the CPU (refused for a drawing); `auto`
    /// takes the CPU for [`Need::CpuUnlessGpu`] on a machine without a GPU,
    /// else starts a device and falls back to the CPU, announced, when no
    /// Vulkan driver or device is there and the work has a CPU algorithm. A
    /// device named outright (`gpu`, `lavapipe`, an index, a name) is that
    /// device or an error.
    pub fn choose(options: &MachineOptions, need: Need) -> Result<Chosen> {
        if Self::cpu_first(options, need)? {
            return Ok(Chosen {
                machine: None,
                fallback: None,
            });
        }
        match Machine::new(options) {
            Ok(machine) => Ok(Chosen {
                machine: Some(machine),
                fallback: None,
            }),
            Err(e) => Self::instead_of_device(options, need, e),
        }
    }

    /// Whether the rule takes the CPU without trying a device: `cpu`
    /// (an error for a drawing), or `auto` for [`Need::CpuUnlessGpu`] on a
    /// machine without a GPU.
    pub fn cpu_first(options: &MachineOptions, need: Need) -> Result<bool> {
        match (&options.device, need) {
            (DeviceChoice::Cpu, Need::Drawing(what)) => Err(drawn_only(what)),
            (DeviceChoice::Cpu, _) => Ok(true),
            (DeviceChoice::Auto, Need::CpuUnlessGpu) => Ok(!has_gpu()),
            _ => Ok(false),
        }
    }

    /// What takes a device's place when it fails to start with `error`: the
    /// CPU, announced, where the choice was `auto`, the failure is that no
    /// driver or device is there, and the work has a CPU algorithm.
    pub fn instead_of_device(options: &MachineOptions, need: Need, error: Error) -> Result<Chosen> {
        match error {
            Error::NoVulkan(_) | Error::NoDevice(_)
                if options.device == DeviceChoice::Auto && !matches!(need, Need::Drawing(_)) =>
            {
                Ok(Chosen {
                    machine: None,
                    fallback: Some(format!("{error}; computing on the CPU")),
                })
            }
            e => Err(e),
        }
    }

    /// The device's machine; `None` on the CPU.
    pub fn machine(&self) -> Option<&'m Machine> {
        match *self {
            Backend::Device(machine) => Some(machine),
            Backend::Cpu => None,
        }
    }

    /// The device's machine, or an error naming `what` as a drawing that
    /// needs one.
    pub fn device_for(&self, what: &str) -> Result<&'m Machine> {
        self.machine().ok_or_else(|| drawn_only(what))
    }

    /// The device's name, or `cpu`.
    pub fn name(&self) -> &str {
        match *self {
            Backend::Device(machine) => machine.device_name(),
            Backend::Cpu => "cpu",
        }
    }
}

/// The refusal of a drawing without a device.
pub(crate) fn drawn_only(what: &str) -> Error {
    Error::Unsupported(format!(
        "{what} on the CPU: it is drawn by a Vulkan device; choose a device (auto, lavapipe, \
         gpu) instead of cpu"
    ))
}

impl<'m> From<&'m Machine> for Backend<'m> {
    fn from(machine: &'m Machine) -> Self {
        Backend::Device(machine)
    }
}
