//! A machine's timeline as a Chrome trace, which Perfetto and
//! `chrome://tracing` open.

use pixgeo::machine::Timeline;
use serde_json::{json, Value};

/// `timeline` in the Chrome trace event format: the host's spans on one track
/// and the device's passes on another, in microseconds.
pub fn chrome_trace(timeline: &Timeline) -> Value {
    let track = |tid: u32, name: &str| json!({"name": "thread_name", "ph": "M", "pid": 1, "tid": tid, "args": {"name": name}});
    let mut events = Vec::from([track(1, "host"), track(2, "device")]);
    for span in &timeline.host {
        events.push(json!({
            "name": span.name, "ph": "X", "pid": 1, "tid": 1,
            "ts": span.start_ms * 1e3, "dur": span.ms * 1e3,
        }));
    }
    for pass in &timeline.passes {
        if let Some(ms) = pass.gpu_ms {
            events.push(json!({
                "name": pass.label, "ph": "X", "pid": 1, "tid": 2,
                "ts": pass.start_ms * 1e3, "dur": ms * 1e3,
            }));
        }
    }
    json!({"traceEvents": events, "displayTimeUnit": "ms"})
}
