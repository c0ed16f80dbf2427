//! `hya generate ROBOT.urdf --name Name [--parametric] [--stats]`: unrolled dynamics for a URDF.

use std::io::Write;

use crate::CliError;

/// Parameters of `hya generate`.
#[derive(Debug, clap::Args)]
pub struct GenerateArgs {
    /// The URDF file.
    urdf: String,
    /// The generated type's name (a Rust identifier).
    #[arg(long)]
    name: String,
    /// Generate the type that holds the inertial parameters as data.
    #[arg(long)]
    parametric: bool,
    /// Print each function's operation counts instead of the code.
    #[arg(long)]
    stats: bool,
}

/// Writes the generated code, or its operation counts, to `output`.
pub fn run(args: &GenerateArgs, output: &mut impl Write) -> Result<(), CliError> {
    let loaded = hya_urdf::load_file(&args.urdf).map_err(|e| CliError::Input(e.to_string()))?;
    for warning in &loaded.warnings {
        eprintln!("hya: warning: {}: {warning}", args.urdf);
    }
    if let Some(warning) = hya_codegen::size_warning(&loaded.model) {
        eprintln!("hya: warning: {}: {warning}", args.urdf);
    }
    let generate = if args.parametric { hya_codegen::generate_parametric } else { hya_codegen::generate };
    let generated = generate(&loaded, &args.name).map_err(|e| CliError::Input(e.to_string()))?;
    let text = if args.stats { generated.stats_table() } else { generated.source };
    write!(output, "{text}")?;
    Ok(())
}
