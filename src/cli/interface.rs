//! `spar interface`: solve one interface and print every outgoing wave.
//!
//! ```text
//! spar interface --from calcite --to air --axis 0,1,1 --incident 0.3,0,-1 --mode e
//! spar interface --from air --to n-bk7 --incident 1,0,-1 --mode s --json
//! ```
//!
//! The incident wave comes from the `--from` medium (side + of the
//! interface, into which `--normal` points) and must carry energy toward the
//! interface. `--json` prints one object:
//! `{"waves":[{"side","mode","k","ray","evanescent","energy"}…],"energy_sum"}`
//! with the two reflected modes first, then the two transmitted ones. `k` is
//! the real part of the wave vector (units of the vacuum wave number; for an
//! evanescent wave its normal component is complex and only the real part is
//! printed), `ray` the unit energy direction (tangential for an evanescent
//! wave), `energy` the fraction of the incident normal energy flux.

use super::error::CliError;
use crate::material::Material;
use crate::optics::medium::default_crystal_x;
use crate::optics::{Interface, InterfaceError, Medium, Mode, Scattering, Side};
use glam::DVec3;
use std::io::Write;

/// Solve one interface: every outgoing wave for one incident wave.
#[derive(clap::Args, Debug)]
pub struct InterfaceArgs {
    /// Medium of the incident wave: a built-in name (e.g. air, n-bk7,
    /// calcite, quartz, sapphire, diamond, topaz, peridot), `iso:N`,
    /// `uniaxial:NO:NE` or `biaxial:NX:NY:NZ`.
    #[arg(long, value_name = "MEDIUM", required_unless_present = "describe")]
    pub from: Option<String>,
    /// Medium on the other side of the interface (same forms as --from).
    #[arg(long, value_name = "MEDIUM", required_unless_present = "describe")]
    pub to: Option<String>,
    /// Describe one medium instead of solving an interface: its indices at
    /// --wavelength, its axes (oriented by --axis and --axis-x) and, for a
    /// biaxial crystal, the angle 2V between its optic axes and their
    /// directions.
    #[arg(long, value_name = "MEDIUM", conflicts_with_all = ["from", "to", "incident", "mode", "normal", "json"])]
    pub describe: Option<String>,
    /// Optic axis of whichever side is uniaxial, or crystal z of a biaxial
    /// side, `x,y,z`.
    #[arg(
        long,
        value_name = "X,Y,Z",
        default_value = "0,0,1",
        allow_hyphen_values = true
    )]
    pub axis: String,
    /// Crystal x of a biaxial side, `x,y,z` (orthogonalized against
    /// --axis). Without it: +x, or +y when --axis lies within 45° of ±x.
    #[arg(long = "axis-x", value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub axis_x: Option<String>,
    /// Interface normal, `x,y,z`, pointing into the --from medium.
    #[arg(
        long,
        value_name = "X,Y,Z",
        default_value = "0,0,1",
        allow_hyphen_values = true
    )]
    pub normal: String,
    /// Direction of the incident wave vector, `x,y,z`, pointing toward the
    /// interface.
    #[arg(
        long,
        value_name = "X,Y,Z",
        allow_hyphen_values = true,
        required_unless_present = "describe"
    )]
    pub incident: Option<String>,
    /// Mode of the incident wave: s or p (isotropic medium), o or e
    /// (uniaxial crystal), fast or slow (biaxial crystal).
    #[arg(
        long,
        value_name = "s|p|o|e|fast|slow",
        required_unless_present = "describe"
    )]
    pub mode: Option<String>,
    /// Vacuum wavelength in nm.
    #[arg(
        long,
        value_name = "NM",
        default_value_t = 589.3,
        allow_hyphen_values = true
    )]
    pub wavelength: f64,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Parse `x,y,z` into a finite non-zero vector.
fn parse_vector(text: &str, flag: &str) -> Result<DVec3, CliError> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let bad = || CliError::input(format!("--{flag} `{text}`: expected three numbers `x,y,z`"));
    if parts.len() != 3 {
        return Err(bad());
    }
    let mut v = [0.0; 3];
    for (x, p) in v.iter_mut().zip(&parts) {
        *x = p.parse::<f64>().map_err(|_| bad())?;
    }
    let v = DVec3::from_array(v);
    if !v.is_finite() {
        return Err(CliError::input(format!("--{flag} `{text}` must be finite")));
    }
    if v.length_squared() == 0.0 || !v.length().is_finite() || v.length() == 0.0 {
        return Err(CliError::input(format!(
            "--{flag} `{text}` must be a non-zero vector"
        )));
    }
    Ok(v)
}

fn describe(name: &str, m: &Medium) -> String {
    match m {
        Medium::Isotropic { n } => format!("{name} (isotropic, n = {n:.6})"),
        Medium::Uniaxial { n_o, n_e, axis } => format!(
            "{name} (uniaxial, n_o = {n_o:.6}, n_e = {n_e:.6}, axis = ({:.4}, {:.4}, {:.4}))",
            axis.x, axis.y, axis.z
        ),
        Medium::Biaxial { n, x, z } => {
            let two_v = crate::optics::anisotropic::half_optic_angle(*n)
                .map_or("undefined (isotropic)".to_string(), |v| {
                    format!("{:.3}°", 2.0 * v.to_degrees())
                });
            format!(
                "{name} (biaxial, n_x = {:.6}, n_y = {:.6}, n_z = {:.6}, \
                 crystal x = ({:.4}, {:.4}, {:.4}), z = ({:.4}, {:.4}, {:.4}), 2V = {two_v})",
                n[0], n[1], n[2], x.x, x.y, x.z, z.x, z.y, z.z
            )
        }
    }
}

/// `--describe MEDIUM`: the medium at --wavelength, oriented by --axis and
/// --axis-x, and for a biaxial crystal its optic axes (the wave normals of
/// equal index, `optics::anisotropic::optic_axes`).
fn describe_medium(args: &InterfaceArgs, name: &str) -> Result<String, CliError> {
    let axis = parse_vector(&args.axis, "axis")?;
    let lambda = wavelength(args)?;
    let m = Material::parse(name).map_err(|e| CliError::input(format!("--describe: {e}")))?;
    let m = orienter(args, axis)?(m, "describe")?;
    let medium = m.medium(lambda, axis);
    check_indices(m.name(), &medium, lambda)?;
    let mut text = format!("{} at {lambda} nm", describe(name, &medium));
    if let Some(axes) = crate::optics::anisotropic::optic_axes(&medium) {
        for (i, a) in axes.iter().enumerate() {
            text += &format!(
                "\noptic axis {}: ({:.5}, {:.5}, {:.5})",
                i + 1,
                a.x,
                a.y,
                a.z
            );
        }
    }
    Ok(text)
}

fn check_indices(name: &str, m: &Medium, lambda: f64) -> Result<(), CliError> {
    let ok = |n: f64| n.is_finite() && n > 0.0;
    let good = match *m {
        Medium::Isotropic { n } => ok(n),
        Medium::Uniaxial { n_o, n_e, .. } => ok(n_o) && ok(n_e),
        Medium::Biaxial { n, .. } => n.into_iter().all(ok),
    };
    if good {
        Ok(())
    } else {
        Err(CliError::input(format!(
            "{name} has no usable refractive index at {lambda} nm (outside its dispersion model)"
        )))
    }
}

/// Build the interface and solve it; every user error becomes
/// an input error (exit status 2).
pub fn solve(args: &InterfaceArgs) -> Result<(Interface, Scattering), CliError> {
    let given = |v: &Option<String>, flag: &str| {
        v.clone()
            .ok_or_else(|| CliError::input(format!("--{flag} is needed to solve an interface")))
    };
    let (from_name, to_name) = (given(&args.from, "from")?, given(&args.to, "to")?);
    let (incident_text, mode_text) = (
        given(&args.incident, "incident")?,
        given(&args.mode, "mode")?,
    );
    let normal = parse_vector(&args.normal, "normal")?;
    let incident = parse_vector(&incident_text, "incident")?;
    let axis = parse_vector(&args.axis, "axis")?;
    let lambda = wavelength(args)?;
    let from = Material::parse(&from_name).map_err(|e| CliError::input(format!("--from: {e}")))?;
    let to = Material::parse(&to_name).map_err(|e| CliError::input(format!("--to: {e}")))?;
    let orient = orienter(args, axis)?;
    let from = orient(from, "from")?;
    let to = orient(to, "to")?;
    let m_from = from.medium(lambda, axis);
    let m_to = to.medium(lambda, axis);
    check_indices(from.name(), &m_from, lambda)?;
    check_indices(to.name(), &m_to, lambda)?;
    let mode = Mode::parse(&mode_text).ok_or_else(|| {
        CliError::input(format!(
            "--mode `{mode_text}`: expected s, p, o or e, or fast or slow (biaxial)"
        ))
    })?;
    solve_parsed(
        (m_from, m_to),
        (from.name(), mode),
        (normal, incident, &incident_text),
    )
}

/// --wavelength, checked.
fn wavelength(args: &InterfaceArgs) -> Result<f64, CliError> {
    let lambda = args.wavelength;
    if !(lambda.is_finite() && lambda > 0.0) {
        return Err(CliError::input(format!(
            "--wavelength {lambda} must be a positive number of nanometres"
        )));
    }
    Ok(lambda)
}

/// Orients a biaxial material by --axis (crystal z) and --axis-x; other
/// materials pass unchanged.
#[allow(clippy::type_complexity)]
fn orienter(
    args: &InterfaceArgs,
    axis: DVec3,
) -> Result<impl Fn(Material, &str) -> Result<Material, CliError> + '_, CliError> {
    // No --axis-x: the deterministic default orthogonal to --axis
    // (optics::medium::default_crystal_x); a given one parallel to --axis
    // is refused.
    let axis_x = match &args.axis_x {
        Some(text) => Some(parse_vector(text, "axis-x")?),
        None => None,
    };
    Ok(
        move |m: Material, flag: &str| -> Result<Material, CliError> {
            if !m.is_biaxial() {
                return Ok(m);
            }
            let name = m.name().to_string();
            let x = axis_x.unwrap_or_else(|| default_crystal_x(axis));
            m.with_crystal_axes(axis, x)
                .map_err(|e| match &args.axis_x {
                    Some(given) => CliError::input(format!(
                "--{flag} {}: --axis-x `{given}` is parallel to --axis `{}`: a biaxial crystal's x \
                 axis needs a part normal to its z axis",
                name, args.axis
            )),
                    None => {
                        CliError::input(format!("--{flag} {name}: --axis `{}`: {e}", args.axis))
                    }
                })
        },
    )
}

/// The interface solve once every flag is parsed.
fn solve_parsed(
    (m_from, m_to): (Medium, Medium),
    (from_name, mode): (&str, Mode),
    (normal, incident, incident_text): (DVec3, DVec3, &str),
) -> Result<(Interface, Scattering), CliError> {
    if !mode.exists_in(&m_from) {
        let has = if m_from.is_isotropic() {
            "it is isotropic: use --mode s or p"
        } else if m_from.is_biaxial() {
            "it is a biaxial crystal: use --mode fast or slow"
        } else {
            "it is a uniaxial crystal: use --mode o or e"
        };
        return Err(CliError::input(format!(
            "--mode {}: the --from medium {from_name} has no such wave; {has}",
            mode.name(),
        )));
    }
    let iface = Interface::new(normal, m_from, m_to)?;
    if incident.dot(iface.normal()) >= 0.0 {
        return Err(CliError::input(format!(
            "--incident `{}` points away from the interface: --normal points into the \
             --from medium, so an incident wave needs incident · normal < 0",
            incident_text
        )));
    }
    let scattering = iface
        .solve_direction(Side::Plus, mode, incident)
        .map_err(|e| match e {
            InterfaceError::NotIncident => CliError::input(format!(
                "--incident `{}`: this {} wave's energy flows away from the interface \
                 (near grazing an extraordinary wave's ray and wave vector can point to \
                 opposite sides of the interface)",
                incident_text,
                mode.name()
            )),
            other => other.into(),
        })?;
    if scattering
        .outgoing
        .iter()
        .any(|o| !o.energy.is_finite() || !o.amplitude.re.is_finite())
    {
        return Err(CliError::internal(
            "the interface solve produced a non-finite value",
        ));
    }
    Ok((iface, scattering))
}

pub fn run(args: &InterfaceArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let io = |e: std::io::Error| CliError::internal(format!("cannot write output: {e}"));
    if let Some(name) = &args.describe {
        return writeln!(out, "{}", describe_medium(args, name)?).map_err(io);
    }
    let (iface, sc) = solve(args)?;
    let side_name = |s: Side| {
        if s == sc.incident.side {
            "reflected"
        } else {
            "transmitted"
        }
    };
    if args.json {
        let waves: Vec<serde_json::Value> = sc
            .outgoing
            .iter()
            .map(|o| {
                let k = o.wave.k.re;
                let r = o.wave.ray;
                serde_json::json!({
                    "side": side_name(o.wave.side),
                    "mode": o.wave.mode.name(),
                    "k": [k.x, k.y, k.z],
                    "ray": [r.x, r.y, r.z],
                    "evanescent": o.wave.evanescent,
                    "energy": o.energy,
                })
            })
            .collect();
        let doc = serde_json::json!({ "waves": waves, "energy_sum": sc.energy_sum() });
        writeln!(out, "{doc}").map_err(io)?;
        return Ok(());
    }
    let v = |d: DVec3| format!("({:>8.5}, {:>8.5}, {:>8.5})", d.x, d.y, d.z);
    let i = &sc.incident;
    writeln!(
        out,
        "from {}",
        describe(
            args.from.as_deref().unwrap_or_default(),
            iface.medium(Side::Plus)
        )
    )
    .map_err(io)?;
    writeln!(
        out,
        "to   {}",
        describe(
            args.to.as_deref().unwrap_or_default(),
            iface.medium(Side::Minus)
        )
    )
    .map_err(io)?;
    writeln!(
        out,
        "wavelength {} nm; unit normal {} points into the incident medium",
        args.wavelength,
        v(iface.normal())
    )
    .map_err(io)?;
    writeln!(
        out,
        "incident {} wave: k {}  ray {}",
        i.mode.name(),
        v(i.k.re),
        v(i.ray)
    )
    .map_err(io)?;
    writeln!(out).map_err(io)?;
    writeln!(
        out,
        "{:<12} {:<4} {:<30} {:<22} {:<30} {:>10}",
        "side", "mode", "k (real part)", "q = k·N", "ray", "energy"
    )
    .map_err(io)?;
    for o in &sc.outgoing {
        let q = o.wave.q;
        let q = if o.wave.evanescent {
            format!("{:.6}{:+.6}i", q.re, q.im)
        } else {
            format!("{:.6}", q.re)
        };
        let energy = if o.wave.evanescent {
            "evanescent".to_string()
        } else {
            format!("{:.8}", o.energy)
        };
        writeln!(
            out,
            "{:<12} {:<4} {:<30} {:<22} {:<30} {:>10}",
            side_name(o.wave.side),
            o.wave.mode.name(),
            v(o.wave.k.re),
            q,
            v(o.wave.ray),
            energy
        )
        .map_err(io)?;
    }
    writeln!(out).map_err(io)?;
    writeln!(out, "energy sum {:.12}", sc.energy_sum()).map_err(io)?;
    Ok(())
}
