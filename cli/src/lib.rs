//! The pixgeo command-line tool, as a library: [`main_with`] runs it on
//! the arguments given. The `pixgeo` binary and the Python package's
//! `pixgeo` command both call it.

#![forbid(unsafe_code)]

/// `println!` for answers: a reader that has gone (`| head`) ends the program
/// quietly, as other Unix tools do; stdout that cannot be written (a full disk)
/// is an error with a non-zero exit.
macro_rules! outln {
    ($($arg:tt)*) => { $crate::answer_line(format_args!($($arg)*)) };
}

/// A message other than an error on stderr: silent under `-q`.
macro_rules! note {
    ($($arg:tt)*) => { if !$crate::quiet() { $crate::say(format_args!($($arg)*)) } };
}

mod alpha;
mod area;
mod cells;
mod delaunay;
mod device;
mod distances;
mod envelope;
mod gallery;
mod homothet;
mod input;
mod interpolate;
mod lloyd;
mod mask;
mod progress;
mod settle;
mod shell;
mod text;
mod transform;
mod voronoi;
use pixgeo_io::write;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

/// Planar geometry computed by rendering: Voronoi diagrams as the lower envelope of
/// cones drawn with a depth test (M. Denny, Algorithmic Geometry via Graphics
/// Hardware, 2003), on any Vulkan device; without a GPU on Mesa's lavapipe.
///
/// Environment: PIXGEO_DEVICE (auto, gpu, lavapipe, an index, or part of a
/// device name; cpu for the thesis's CPU pixel algorithms) picks where to
/// compute; PIXGEO_VALIDATION=1 turns on the Khronos validation layer and makes
/// every message an error.
#[derive(Parser)]
#[command(name = "pixgeo", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// No messages on stderr but errors: no summaries, no files-written lines,
    /// no progress bars. Answers still go to stdout.
    #[arg(short, long, global = true)]
    quiet: bool,
    /// Write a Chrome trace of the run to FILE (open it in Perfetto or
    /// chrome://tracing): the host's phases and runs, and each pass on the
    /// device, labelled by what it drew or dispatched.
    #[arg(long, global = true, value_name = "FILE.json")]
    trace: Option<std::path::PathBuf>,
}

/// Every machine the command starts records into this: its passes' device
/// times go into `--json`'s `gpu_ms` and the `--trace` file.
fn profiler() -> &'static pixgeo::machine::Profiler {
    static PROFILER: std::sync::OnceLock<pixgeo::machine::Profiler> = std::sync::OnceLock::new();
    PROFILER.get_or_init(pixgeo::machine::Profiler::new)
}

/// Set once from `-q`, before any command runs.
static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

fn quiet() -> bool {
    QUIET.load(std::sync::atomic::Ordering::Relaxed)
}

/// Tells which files a command wrote (each `Some` output path), unless `-q`,
/// once they are in place.
fn wrote<'a>(paths: impl IntoIterator<Item = Option<&'a std::path::Path>>) {
    for path in paths.into_iter().flatten() {
        write::output::announce(path);
    }
}

#[derive(Subcommand)]
enum Command {
    Voronoi(Box<voronoi::Args>),
    Hausdorff(distances::HausdorffArgs),
    Diameter(distances::DiameterArgs),
    Maxdist(distances::MaxDistArgs),
    Settle(Box<settle::Args>),
    Lloyd(Box<lloyd::Args>),
    Interpolate(Box<interpolate::Args>),
    Enclose(homothet::EncloseArgs),
    Empty(homothet::EmptyArgs),
    Alpha(alpha::Args),
    Triangle(area::TriangleArgs),
    Quadrangle(area::QuadrangleArgs),
    Delaunay(Box<delaunay::Args>),
    Transform(transform::Args),
    Gallery(gallery::Args),
    Completions(shell::CompletionsArgs),
    Man(shell::ManArgs),
}

/// Writes a line to stderr. A closed or full stderr drops the message: the
/// exit code still says what happened.
fn say(line: std::fmt::Arguments) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// Writes `text` as the answer on stdout, as [`answer_line`] does a line.
fn answer(text: &str) {
    answer_line(format_args!("{}", text.trim_end_matches('\n')));
}

fn answer_line(line: std::fmt::Arguments) {
    use std::io::Write;
    // An output holds stdout: the answer's lines go beside the messages.
    if write::output::stdout_taken() {
        return say(line);
    }
    let mut out = std::io::stdout().lock();
    let written = out
        .write_fmt(line)
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush());
    match written {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => {
            say(format_args!("Error: writing the answer to stdout: {e}"));
            std::process::exit(1);
        }
    }
}

/// Runs the command line on `args` (the program's name first) and returns
/// its exit status: 0, 1 with the error on stderr, 2 for a usage error (as
/// clap reports it), 128 plus the signal's number at SIGINT, SIGTERM or SIGHUP.
pub fn main_with<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    match main_result(args) {
        Ok(()) => 0,
        Err(error) => {
            say(format_args!("Error: {}", report(&error)));
            1
        }
    }
}

/// An error and its causes, as anyhow writes them; with a backtrace (where
/// `RUST_BACKTRACE` captured one) only for a bug of pixgeo's own.
fn report(error: &anyhow::Error) -> String {
    let internal = error.chain().any(|e| {
        matches!(
            e.downcast_ref::<pixgeo::Error>(),
            Some(pixgeo::Error::Internal(_))
        )
    });
    if internal {
        return format!("{error:?}");
    }
    let causes: Vec<String> = error.chain().skip(1).map(|e| e.to_string()).collect();
    let mut text = error.to_string();
    if !causes.is_empty() {
        text += "\n\nCaused by:";
        for (i, cause) in causes.iter().enumerate() {
            text += &match causes.len() {
                1 => format!("\n    {cause}"),
                _ => format!("\n    {i}: {cause}"),
            };
        }
    }
    text
}

fn main_result<I, T>(args: I) -> anyhow::Result<()>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let matches = Cli::command().get_matches_from(args);
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    QUIET.store(cli.quiet, std::sync::atomic::Ordering::Relaxed);
    let name = matches.subcommand_name().unwrap_or_default();
    let json = matches
        .subcommand()
        .and_then(|(_, sub)| sub.try_get_one::<bool>("json").ok().flatten())
        == Some(&true);
    on_signals_abandon();
    write::output::answers_as_json(json);
    let phase = profiler().phase(format!("pixgeo {name}"));
    let mut done = match &cli.trace {
        Some(path) => write::output::check_extension(path, "json", "traces")
            .and_then(|()| write::output::claim(path, "--trace"))
            .map_err(anyhow::Error::from),
        None => Ok(()),
    };
    done = done.and_then(|()| run(cli.command));
    drop(phase);
    if let (Some(path), Ok(())) = (&cli.trace, &done) {
        done = write_trace(path);
    }
    done = done.and_then(|()| put_in_place());
    if done.is_err() {
        write::output::abandon();
    }
    if let (true, Err(error)) = (json, &done) {
        // A program reading the answer reads the failure in the same envelope.
        outln!("{}", envelope::error(name, error));
    }
    done
}

/// Puts the finished outputs in place and tells of them (unless `-q`).
fn put_in_place() -> anyhow::Result<()> {
    for path in write::output::finish()? {
        note!("wrote {}", path.display());
    }
    Ok(())
}

/// The run's host phases and device passes as a Chrome trace.
fn write_trace(path: &std::path::Path) -> anyhow::Result<()> {
    let trace = serde_json::to_string(&pixgeo_io::trace::chrome_trace(&profiler().timeline()))?;
    write::output::write_text(path, "json", "traces", |w| w.write_all(trace.as_bytes()))?;
    wrote([Some(path)]);
    Ok(())
}

fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Voronoi(args) => voronoi::run(*args),
        Command::Hausdorff(args) => distances::hausdorff(args),
        Command::Diameter(args) => distances::diameter(args),
        Command::Maxdist(args) => distances::maxdist(args),
        Command::Settle(args) => settle::run(*args),
        Command::Lloyd(args) => lloyd::run(*args),
        Command::Interpolate(args) => interpolate::run(*args),
        Command::Enclose(args) => homothet::enclose(args),
        Command::Empty(args) => homothet::empty(args),
        Command::Alpha(args) => alpha::run(args),
        Command::Triangle(args) => area::triangle(args),
        Command::Quadrangle(args) => area::quadrangle(args),
        Command::Delaunay(args) => delaunay::run(*args),
        Command::Transform(args) => transform::run(args),
        // Each picture's command puts its outputs in place before the next.
        Command::Gallery(args) => gallery::run(args, |command| {
            run(command)?;
            put_in_place()
        }),
        Command::Completions(args) => shell::completions(args),
        Command::Man(args) => shell::man(args),
    }
}

/// Removes every temporary file and exits at SIGINT, SIGTERM and SIGHUP
/// with 128 plus the signal's number (130, 143, 129), as shells and
/// supervisors read a command ended by a signal.
pub fn on_signals_abandon() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    static WATCHING: std::sync::Once = std::sync::Once::new();
    WATCHING.call_once(|| {
        // Signals are only refused where the process cannot take them at all.
        if let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) {
            std::thread::spawn(move || {
                if let Some(signal) = signals.forever().next() {
                    write::output::abandon();
                    std::process::exit(128 + signal);
                }
            });
        }
    });
}
