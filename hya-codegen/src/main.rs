//! `hya-codegen ROBOT.urdf --name Name [--parametric] [--stats]`: writes a robot's generated dynamics to stdout
//! (with `--parametric`, the type that holds its inertial parameters),
//! or with `--stats` each generated function's count of adds, multiplies and `sin_cos` calls.

use std::process::ExitCode;

const USAGE: &str = "usage: hya-codegen ROBOT.urdf --name TypeName [--parametric] [--stats]";

fn main() -> ExitCode {
    match run(std::env::args().skip(1).collect()) {
        Ok(output) => {
            print!("{output}");
            ExitCode::SUCCESS
        }
        Err(message) => {
            eprintln!("hya-codegen: {message}");
            ExitCode::from(2)
        }
    }
}

fn run(args: Vec<String>) -> Result<String, String> {
    let mut path = None;
    let mut name = None;
    let mut stats = false;
    let mut parametric = false;
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--name" => name = Some(args.next().ok_or("--name needs a type name")?),
            "--stats" => stats = true,
            "--parametric" => parametric = true,
            "-h" | "--help" => return Ok(format!("{USAGE}\n")),
            flag if flag.starts_with("--") => return Err(format!("unknown option {flag}\n{USAGE}")),
            _ if path.is_none() => path = Some(arg),
            _ => return Err(format!("unexpected argument {arg:?}\n{USAGE}")),
        }
    }
    let path = path.ok_or(USAGE)?;
    let name = name.ok_or(USAGE)?;
    let loaded = hya_urdf::load_file(&path).map_err(|e| e.to_string())?;
    for warning in &loaded.warnings {
        eprintln!("hya-codegen: warning: {path}: {warning}");
    }
    if let Some(warning) = hya_codegen::size_warning(&loaded.model) {
        eprintln!("hya-codegen: warning: {path}: {warning}");
    }
    let generate = if parametric { hya_codegen::generate_parametric } else { hya_codegen::generate };
    let generated = generate(&loaded, &name).map_err(|e| e.to_string())?;
    Ok(if stats { generated.stats_table() } else { generated.source })
}
