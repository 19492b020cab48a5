//! `appel`: the command-line front end. Each subcommand lives in its own file; the library does all
//! the work.

mod bench_cmd;
mod convert_cmd;
mod gen_cmd;
mod inside_cmd;
mod memory;
mod render_cmd;
mod render_frames;
mod scene_args;
mod scenes_cmd;
mod view;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "appel",
    version,
    about = "Appel: a fast, correct CPU ray tracer"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file (or a built-in scene) to an image.
    Render(Box<render_cmd::RenderArgs>),
    /// Measure acceleration structures: build time, memory and ray throughput.
    Bench(Box<bench_cmd::BenchArgs>),
    /// Write a scene's or mesh's triangles as one binary PLY, in Appel's triangle order.
    Convert(convert_cmd::ConvertArgs),
    /// Write a large reproducible scene (ecosystem or city) from a seed.
    Gen(gen_cmd::GenArgs),
    /// Tell, for each point of a list, whether it lies inside a closed mesh.
    Inside(inside_cmd::InsideArgs),
    /// List the built-in scenes, or print one as a scene file to edit.
    Scenes(scenes_cmd::ScenesArgs),
    /// Serve an interactive viewer of a scene, or the lecture's 2D structures, in the browser.
    View(Box<view::ViewArgs>),
}

/// Rust starts programs with SIGPIPE ignored, so a `println!` after the reader of stdout has gone
/// (`appel bench ... | head`) panics. A command-line tool should end quietly then, as Unix tools
/// do. The viewer keeps SIGPIPE ignored: a browser closing its socket is an error the server
/// handles, not the end of the server.
#[cfg(unix)]
fn end_quietly_when_stdout_closes() {
    // SAFETY: called first in `main`, before any other thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    #[cfg(unix)]
    if !matches!(cli.command, Command::View(_)) {
        end_quietly_when_stdout_closes();
    }
    let result = match cli.command {
        Command::Render(args) => render_cmd::run(*args),
        Command::Scenes(args) => scenes_cmd::run(args),
        Command::Bench(args) => bench_cmd::run(*args),
        Command::Convert(args) => convert_cmd::run(args),
        Command::Inside(args) => inside_cmd::run(args),
        Command::Gen(args) => gen_cmd::run(args),
        Command::View(args) => view::run(*args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
