//! Scene files: a small TOML table of the scene and solver flags, so a setup can be kept and
//! shared. Keys are the long flag names without dashes (`scene = "bunny"`, `iterations = 15`,
//! `energy-aware = "global"`, `no-gravity = true`). `--scene-file PATH` reads one: its flags are
//! inserted right after the subcommand, so flags given on the command line override it.
//! `--save-scene PATH` writes the flags a run was given.

use std::ffi::OsString;
use std::path::Path;

use anyhow::{Context, bail};
use clap::parser::ValueSource;

/// The command line with every `--scene-file PATH` (or `--scene-file=PATH`) replaced by the
/// file's flags, placed after the subcommand.
pub fn expand(args: impl IntoIterator<Item = OsString>) -> anyhow::Result<Vec<OsString>> {
    let mut args: Vec<OsString> = args.into_iter().collect();
    let mut from_files = Vec::new();
    let mut i = 0;
    while i < args.len() {
        let arg = args[i].to_string_lossy().into_owned();
        let path = if arg == "--scene-file" {
            let Some(p) = args.get(i + 1).cloned() else { bail!("--scene-file needs a path") };
            args.drain(i..i + 2);
            p
        } else if let Some(p) = arg.strip_prefix("--scene-file=") {
            let p = OsString::from(p);
            args.remove(i);
            p
        } else {
            i += 1;
            continue;
        };
        from_files.extend(read(Path::new(&path))?);
    }
    // After the program name and the subcommand (`report energy` has none of these flags).
    let at = args.len().min(2);
    args.splice(at..at, from_files);
    Ok(args)
}

/// The flags stored in the scene file at `path`.
pub fn read(path: &Path) -> anyhow::Result<Vec<OsString>> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read scene file {}", path.display()))?;
    let table: toml::Table =
        text.parse().with_context(|| format!("{} is not a valid TOML scene file", path.display()))?;
    let mut flags = Vec::new();
    for (key, value) in table {
        if key == "scene-file" {
            bail!("{}: a scene file cannot read another ('scene-file')", path.display());
        }
        // `--key=value`, so that a negative number reads as the flag's value.
        let flag = format!("--{key}");
        match value {
            toml::Value::Boolean(true) => flags.push(flag.into()),
            toml::Value::Boolean(false) => {}
            toml::Value::String(s) => flags.push(format!("{flag}={s}").into()),
            toml::Value::Integer(n) => flags.push(format!("{flag}={n}").into()),
            toml::Value::Float(x) => flags.push(format!("{flag}={x}").into()),
            other => bail!("{}: '{key}' must be a string, number or boolean, not {}", path.display(), other.type_str()),
        }
    }
    Ok(flags)
}

/// Writes the flags of `matches` given on the command line or read from a scene file (not
/// defaults, and not `skip`) as a scene file at `path`.
pub fn write(path: &Path, matches: &clap::ArgMatches, skip: &[&str]) -> anyhow::Result<()> {
    let mut table = toml::Table::new();
    for id in matches.ids() {
        let id = id.as_str();
        if skip.contains(&id) || matches.value_source(id) != Some(ValueSource::CommandLine) {
            continue;
        }
        let Some(mut raw) = matches.get_raw(id) else { continue };
        let key = id.replace('_', "-");
        let text = raw.next_back().map(|v| v.to_string_lossy().into_owned()).unwrap_or_else(|| "true".into());
        // Switches (`no-gravity`) read back as booleans.
        let value = match text.as_str() {
            "true" => toml::Value::Boolean(true),
            "false" => continue,
            t => typed(t),
        };
        table.insert(key, value);
    }
    let text = format!("# eapbd scene file: flags of `eapbd simulate` / `render` / `view`\n{table}");
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// A flag's text as the TOML value that reads back to the same text.
fn typed(s: &str) -> toml::Value {
    if let Ok(n) = s.parse::<i64>() {
        return toml::Value::Integer(n);
    }
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x.to_string() == s => toml::Value::Float(x),
        _ => toml::Value::String(s.to_string()),
    }
}
