use anyhow::{bail, Result};
use appel::scene::builtin::BUILTIN_SCENES;

#[derive(clap::Args)]
pub struct ScenesArgs {
    /// Print the named built-in scene as a TOML scene file.
    #[arg(long, value_name = "NAME")]
    write: Option<String>,
}

pub fn run(args: ScenesArgs) -> Result<()> {
    match args.write {
        Some(name) => match BUILTIN_SCENES.iter().find(|(n, _, _)| *n == name) {
            Some((_, _, text)) => print!("{text}"),
            None => bail!(
                "no built-in scene `{name}`; the built-in scenes are: {}",
                BUILTIN_SCENES
                    .iter()
                    .map(|s| s.0)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        },
        None => {
            for (name, about, _) in BUILTIN_SCENES {
                println!("{name:<14} {about}");
            }
        }
    }
    Ok(())
}
