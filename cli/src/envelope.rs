//! The one JSON envelope of every `--json` answer (`cli/schema/`):
//!
//! ```text
//! {"schema": "pixgeo/1", "pixgeo_version", "command", "device", "fallback",
//!  "frame": {"width", "height", "bbox", "origin", "scale", "y_axis", "crs"}
//!  or null,
//!  "timings_ms": {...}, "gpu_ms": {...}, "result": {...}}
//! ```
//!
//! A command hands over its answer as it serializes; the envelope lifts the
//! answer's `*_ms` timings into `timings_ms`, so a result holds answers only;
//! `gpu_ms` holds the device's milliseconds by pass.

use anyhow::Result;
use pixgeo::geometry::Frame;

use crate::{
    input::{World, YAxis},
    write::geotiff::crs_name,
};
use serde::Serialize;
use serde_json::{json, Map, Value};

pub const SCHEMA: &str = "pixgeo/1";

/// Answers longer than this (bytes on one line) are not indented.
const ONE_LINE_FROM: usize = 1 << 16;

/// Prints `result` in the envelope. `device` is the Vulkan device's name, or
/// `cpu`; `frame` is the picture the user asked for, where the command takes one.
/// Large answers (meshes of millions of numbers) come on one line.
pub fn print(
    command: &str,
    device: &str,
    frame: Option<&Frame>,
    result: &impl Serialize,
) -> Result<()> {
    let world = frame.map(|&frame| World {
        frame,
        y_axis: YAxis::Down,
        epsg: None,
        bbox: None,
        cloud_optimized: false,
    });
    print_placed(command, device, world.as_ref(), result)
}

/// The envelope of a command that failed under `--json`: `error` holds the
/// message and its chain of causes, outermost first (`cli/schema/error.json`).
pub fn error(command: &str, error: &anyhow::Error) -> Value {
    let causes: Vec<String> = error.chain().map(|c| c.to_string()).collect();
    let mut body = json!({"message": error.to_string(), "causes": causes});
    if let Some(reason) = reason(error) {
        body["reason"] = reason;
    }
    json!({
        "schema": SCHEMA,
        "pixgeo_version": env!("CARGO_PKG_VERSION"),
        "command": command,
        "error": body,
    })
}

/// Why the input was refused, by kind, where pixgeo refused it.
fn reason(error: &anyhow::Error) -> Option<Value> {
    let why = error.chain().find_map(|cause| match cause.downcast_ref() {
        Some(pixgeo::Error::InvalidInput(why)) => Some(why),
        _ => None,
    })?;
    let mut reason = json!({"kind": why.kind()});
    for (name, number) in why.numbers() {
        reason[name] = json!(number);
    }
    Some(reason)
}

/// [`print()`] for a command whose rasters may run north-up.
pub fn print_world(
    command: &str,
    device: &str,
    world: &World,
    result: &impl Serialize,
) -> Result<()> {
    print_placed(command, device, Some(world), result)
}

fn print_placed(
    command: &str,
    device: &str,
    frame: Option<&World>,
    result: &impl Serialize,
) -> Result<()> {
    let gpu_ms = crate::profiler().timeline().gpu_ms_by_pass();
    let envelope = wrap(
        command,
        device,
        frame,
        serde_json::to_value(result)?,
        serde_json::to_value(gpu_ms)?,
    );
    let line = serde_json::to_string(&envelope)?;
    if line.len() > ONE_LINE_FROM {
        outln!("{line}");
    } else {
        outln!("{}", serde_json::to_string_pretty(&envelope)?);
    }
    Ok(())
}

fn wrap(
    command: &str,
    device: &str,
    frame: Option<&World>,
    mut result: Value,
    gpu_ms: Value,
) -> Value {
    let mut timings = Map::new();
    lift_timings(&mut result, "", &mut timings);
    drop_device(&mut result, device);
    json!({
        "schema": SCHEMA,
        "pixgeo_version": env!("CARGO_PKG_VERSION"),
        "command": command,
        "device": device,
        "fallback": crate::device::fallback(),
        "frame": frame.map(frame_json),
        "timings_ms": timings,
        "gpu_ms": gpu_ms,
        "result": result,
    })
}

/// Moves every `NAME_ms` field of `value`'s objects (not inside arrays) into
/// `timings` as `NAME`, or `PATH.NAME` where two objects time the same name.
fn lift_timings(value: &mut Value, path: &str, timings: &mut Map<String, Value>) {
    let Value::Object(fields) = value else { return };
    let names: Vec<String> = fields.keys().cloned().collect();
    for name in names {
        if let Some(stem) = name.strip_suffix("_ms") {
            let taken = fields.remove(&name).unwrap_or(Value::Null);
            let key = if timings.contains_key(stem) {
                format!("{path}{stem}")
            } else {
                stem.to_string()
            };
            timings.insert(key, taken);
        } else if let Some(inner) = fields.get_mut(&name) {
            lift_timings(inner, &format!("{path}{name}."), timings);
        }
    }
}

/// Removes the answer's own copies of the device's name: it is named once.
fn drop_device(value: &mut Value, device: &str) {
    if let Value::Object(fields) = value {
        if fields.get("device").and_then(Value::as_str) == Some(device) {
            fields.remove("device");
        }
        fields.values_mut().for_each(|v| drop_device(v, device));
    }
}

/// The frame in the user's world: pixel (i, j) has its centre at origin +
/// (i + 0.5, ±(j + 0.5)) / scale, + with y down, - with y up (north-up).
fn frame_json(world: &World) -> Value {
    let frame = &world.frame;
    let origin = world.to_user(frame.origin);
    json!({
        "width": frame.width,
        "height": frame.height,
        "bbox": world.bbox(),
        "origin": [origin.x, origin.y],
        "scale": frame.scale,
        "y_axis": world.y_axis,
        "crs": crs_name(world.epsg),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timings_leave_the_result_and_the_frame_gives_its_box() {
        // North-up: pixgeo computes in the mirrored world, whose frame starts
        // at y = -4; the envelope gives the user's box and corner.
        let frame = Frame::with_bbox(4, Some(2), [0.0, -4.0, 8.0, 0.0]).unwrap();
        let world = World {
            frame,
            y_axis: YAxis::Up,
            epsg: Some(4326),
            bbox: None,
            cloud_optimized: false,
        };
        let v = wrap(
            "voronoi",
            "llvmpipe",
            Some(&world),
            json!({"sites": 3, "render_ms": 1.5, "stats": {"render_ms": 2, "draw_ms": 3, "device": "llvmpipe"}}),
            json!({"render: ConeFan": 0.5}),
        );
        assert_eq!(v["schema"], "pixgeo/1");
        assert_eq!(
            v["timings_ms"],
            json!({"render": 1.5, "stats.render": 2, "draw": 3})
        );
        assert_eq!(v["result"], json!({"sites": 3, "stats": {}}));
        assert_eq!(v["gpu_ms"], json!({"render: ConeFan": 0.5}));
        assert_eq!(v["frame"]["bbox"], json!([0.0, 0.0, 8.0, 4.0]));
        assert_eq!(v["frame"]["origin"], json!([0.0, 4.0]));
        assert_eq!(v["frame"]["scale"], json!(0.5));
        assert_eq!(v["frame"]["y_axis"], "up");
        assert_eq!(v["frame"]["crs"], "EPSG:4326");
    }
}
