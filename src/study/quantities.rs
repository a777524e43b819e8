//! The quantities an engineer designs with, per printed cycle of a run (columns of
//! `data/<table>.csv`; formulas and units in report/README.md, "Engineering quantities").
//!
//! * A thin film ([`film`]): the load capacity W = ∫(p − p₀) dx with p = ψ/g and p₀ = ψ₀/g (the
//!   pressure the boundary value ψ₀ stands for; ψ = ∫p dx₃, docs/models.md §5.3), the largest
//!   mean pressure p and where it is, the cavitated area, the flow χ·n out through each side and
//!   the shear force of the film on each wall.
//! * A contact problem ([`contact`]): the total contact force Σλᵢ over the active constraints
//!   (the nodal multipliers of the active-set solve), the contact length, the largest contact pressure λᵢ/ℓᵢ (ℓᵢ the length of
//!   boundary a vertex stands for), and per contact side its force.
//!
//! All quantities are per unit depth in the thesis's nondimensional units; the formulas read the
//! solution as the model defines it and add no physics of their own.

use super::contact::{active_loads, CycleState};
use crate::fe::cell_values::evaluate;
use crate::fe::quadrature::{gauss, square};
use crate::fe::DofMap;
use crate::mesh::{Mesh, Side};
use crate::models::contact::ContactBoundary;
use crate::models::thin_film::ThinFilm;

/// Column names.
pub mod names {
    /// W = ∫(ψ − ψ₀)/g dx: the load the film carries above the boundary pressure.
    pub const LOAD_CAPACITY: &str = "load_capacity";
    /// max p = ψ/g over the vertices, and its position.
    pub const MAX_PRESSURE: &str = "max_pressure";
    pub const MAX_PRESSURE_X1: &str = "max_pressure_x1";
    pub const MAX_PRESSURE_X2: &str = "max_pressure_x2";
    /// The area of the cells whose four corners are cavitated (ψ_h ≤ 0).
    pub const CAVITATED_AREA: &str = "cavitated_area";
    /// ∫ χ·n ds over a side (outward normal): the volume flow out through it.
    pub const FLOW: [&str; 4] = ["flow_left", "flow_right", "flow_bottom", "flow_top"];
    /// The shear force of the film on the lower and the upper wall, per component.
    pub const FRICTION: [&str; 4] = [
        "friction_lower_x1",
        "friction_lower_x2",
        "friction_upper_x1",
        "friction_upper_x2",
    ];
    /// Σλᵢ over the contact constraints.
    pub const CONTACT_FORCE: &str = "contact_force";
    /// Σℓᵢ over the vertices in contact.
    pub const CONTACT_LENGTH: &str = "contact_length";
    /// max λᵢ/ℓᵢ.
    pub const MAX_CONTACT_PRESSURE: &str = "max_contact_pressure";
}

/// The quantity columns of a film's rows ([`film`]; `cavitated_area` only where the cavitation
/// model ran).
pub const FILM: &[&str] = &[
    names::LOAD_CAPACITY,
    names::MAX_PRESSURE,
    names::MAX_PRESSURE_X1,
    names::MAX_PRESSURE_X2,
    names::CAVITATED_AREA,
    "flow_left",
    "flow_right",
    "flow_bottom",
    "flow_top",
    "friction_lower_x1",
    "friction_lower_x2",
    "friction_upper_x1",
    "friction_upper_x2",
];

/// The quantity columns of a contact problem's rows ([`contact`]; with two contact sides also
/// `contact_force_<side>`, [`is_side_force`]).
pub const CONTACT: &[&str] = &[
    names::CONTACT_FORCE,
    names::CONTACT_LENGTH,
    names::MAX_CONTACT_PRESSURE,
];

/// The quantities a comparison of runs shows unless it names others: the load a film carries and
/// its peak pressure, the force of a contact and its peak pressure (those of them a run has).
pub const COMPARED: &[&str] = &[
    names::LOAD_CAPACITY,
    names::MAX_PRESSURE,
    names::CONTACT_FORCE,
    names::MAX_CONTACT_PRESSURE,
];

/// Whether `column` is the force of one contact side, `contact_force_<side>`.
pub fn is_side_force(column: &str) -> bool {
    column
        .strip_prefix("contact_force_")
        .is_some_and(|side| SIDES.iter().any(|s| s.name() == side))
}

/// What each quantity column is, with its unit, for the page (`contact_force_<side>` by
/// prefix); `None` for any other column. Units per unit depth of the 2-D model where it is a
/// body (contact), and of the film's plane where it is a film; F force, L length, T time.
pub fn label(column: &str) -> Option<(String, &'static str)> {
    use names::*;
    let fixed = match column {
        LOAD_CAPACITY => ("load capacity W = ∫(p − p₀) dx", "F"),
        MAX_PRESSURE => ("largest pressure p = ψ/g", "F/L²"),
        MAX_PRESSURE_X1 => ("at x₁", "L"),
        MAX_PRESSURE_X2 => ("at x₂", "L"),
        CAVITATED_AREA => ("cavitated area", "L²"),
        "flow_left" => ("outflow, left side", "L³/T"),
        "flow_right" => ("outflow, right side", "L³/T"),
        "flow_bottom" => ("outflow, bottom side", "L³/T"),
        "flow_top" => ("outflow, top side", "L³/T"),
        "friction_lower_x1" => ("shear force on the lower wall, x₁", "F"),
        "friction_lower_x2" => ("shear force on the lower wall, x₂", "F"),
        "friction_upper_x1" => ("shear force on the upper wall, x₁", "F"),
        "friction_upper_x2" => ("shear force on the upper wall, x₂", "F"),
        CONTACT_FORCE => ("contact force Σλᵢ", "F/L"),
        CONTACT_LENGTH => ("contact length", "L"),
        MAX_CONTACT_PRESSURE => ("largest contact pressure λᵢ/ℓᵢ", "F/L²"),
        _ => {
            let side = column.strip_prefix("contact_force_")?;
            return Some((format!("contact force, {side} side"), "F/L"));
        }
    };
    Some((fixed.0.to_string(), fixed.1))
}

/// The sides in the order of [`names::FLOW`].
const SIDES: [Side; 4] = [Side::Left, Side::Right, Side::Bottom, Side::Top];

/// A film solution: ψ_h and, for SubStokes, χ_h as components of `u`.
pub struct FilmSolution<'a> {
    pub film: &'a ThinFilm,
    /// ψ₀ on ∂Ω₂.
    pub boundary_pressure: f64,
    pub u: &'a [f64],
    pub psi: usize,
    /// The components (χ₁, χ₂) where the model solves for the flow rate (SubStokes); else χ
    /// follows from ψ by the Reynolds relation (see [`film`]).
    pub chi: Option<[usize; 2]>,
    /// Whether the cavitation model ran (else no cavitated area is reported).
    pub cavitation: bool,
}

/// The film quantities of a solve (module docs), with the velocity profile of the thin-film
/// models: v_μ(x₃) = ½∂_μp·x₃(x₃ − g) + δv_μ x₃/g (z₀ = 0, v(z₀) = 0, viscosity 1, §5 and §8 of
/// docs/models.md), so that
/// * χ_μ = ∫v_μ dx₃ = −(g³/12)∂_μp + g δv_μ/2 (the Reynolds relation; SubStokes reports its
///   own χ_h),
/// * the shear stress on the lower wall is ∂₃v_μ(0) = −(g/2)∂_μp + δv_μ/g, the force of the
///   film on the upper wall −∂₃v_μ(g) = −(g/2)∂_μp − δv_μ/g,
///
/// with ∇p = (∇ψ_h − ψ_h∇g/g)/g. In a cavitation zone ψ_h = 0 and the formulas keep the
/// Couette shear of a full gap (the model says nothing about a partly filled one).
/// Integrals by the 2×2 Gauss rule on cells and the 2-point rule on boundary faces (the films'
/// cells are rectangles: the weights times the area are exact for them).
pub fn film(mesh: &Mesh, dofs: &DofMap, s: &FilmSolution) -> Vec<(String, f64)> {
    let dv = s.film.upper_wall_velocity;
    let psi0 = s.boundary_pressure;
    let value = |k: usize, c: usize, xi: f64, eta: f64| {
        let shape = mesh.cell_shape(mesh.active()[k]);
        evaluate(&shape, dofs.corner_values(s.u, k, c), xi, eta)
    };
    // ∇p at a point from ψ_h and its gradient.
    let grad_p = |x: [f64; 2], psi: f64, dpsi: [f64; 2]| {
        let (g, dg, _) = s.film.gap(x);
        [0, 1].map(|m| (dpsi[m] - psi * dg[m] / g) / g)
    };
    let (mut load, mut cavitated) = (0.0, 0.0);
    let mut friction = [0.0; 4];
    let rule = square(2);
    for (k, &c) in mesh.active().iter().enumerate() {
        let shape = mesh.cell_shape(c);
        let area = shape.area();
        if s.cavitation && dofs.corner_values(s.u, k, s.psi).iter().all(|&p| p <= 0.0) {
            cavitated += area;
        }
        for &(xi, eta, w) in &rule {
            let x = shape.point(xi, eta);
            let (psi, dpsi) = value(k, s.psi, xi, eta);
            let g = s.film.gap(x).0;
            load += w * area * (psi - psi0) / g;
            let dp = grad_p(x, psi, dpsi);
            for m in 0..2 {
                friction[m] += w * area * (-0.5 * g * dp[m] + dv[m] / g);
                friction[2 + m] += w * area * (-0.5 * g * dp[m] - dv[m] / g);
            }
        }
    }
    let flows = SIDES.map(|side| {
        boundary_integral(mesh, side, |k, xi, eta, normal| {
            let x = mesh.cell_shape(mesh.active()[k]).point(xi, eta);
            let chi = match s.chi {
                Some([c1, c2]) => [value(k, c1, xi, eta).0, value(k, c2, xi, eta).0],
                None => {
                    let (psi, dpsi) = value(k, s.psi, xi, eta);
                    let g = s.film.gap(x).0;
                    let dp = grad_p(x, psi, dpsi);
                    [0, 1].map(|m| -g * g * g / 12.0 * dp[m] + 0.5 * g * dv[m])
                }
            };
            chi[0] * normal[0] + chi[1] * normal[1]
        })
    });
    let (mut top, mut at) = (f64::NEG_INFINITY, [0.0; 2]);
    for (v, &x) in dofs.vertices.coords.iter().enumerate() {
        let p = s.u[v * dofs.n_components + s.psi] / s.film.gap(x).0;
        if p > top {
            (top, at) = (p, x);
        }
    }
    let mut out = vec![
        (names::LOAD_CAPACITY, load),
        (names::MAX_PRESSURE, top),
        (names::MAX_PRESSURE_X1, at[0]),
        (names::MAX_PRESSURE_X2, at[1]),
    ];
    if s.cavitation {
        out.push((names::CAVITATED_AREA, cavitated));
    }
    out.extend(names::FLOW.into_iter().zip(flows));
    out.extend(names::FRICTION.into_iter().zip(friction));
    out.into_iter()
        .map(|(name, value)| (name.to_string(), value))
        .collect()
}

/// ∫ f ds over the side `side` of the mesh's rectangle: f(k, ξ, η, n) at the 2-point Gauss
/// points of each boundary face of an active cell k, with the outward unit normal n.
fn boundary_integral(mesh: &Mesh, side: Side, f: impl Fn(usize, f64, f64, [f64; 2]) -> f64) -> f64 {
    let boxes: Vec<[f64; 4]> = mesh.active().iter().map(|&c| mesh.cell_box(c)).collect();
    let lo = |i: usize| boxes.iter().map(|b| b[i]).fold(f64::INFINITY, f64::min);
    let hi = |i: usize| boxes.iter().map(|b| b[i]).fold(f64::NEG_INFINITY, f64::max);
    let (x0, y0, x1, y1) = (lo(0), lo(1), hi(2), hi(3));
    let (points, weights) = gauss(2);
    let mut sum = 0.0;
    for (k, b) in boxes.iter().enumerate() {
        let (on, normal, length) = match side {
            Side::Left => (b[0] == x0, [-1.0, 0.0], b[3] - b[1]),
            Side::Right => (b[2] == x1, [1.0, 0.0], b[3] - b[1]),
            Side::Bottom => (b[1] == y0, [0.0, -1.0], b[2] - b[0]),
            Side::Top => (b[3] == y1, [0.0, 1.0], b[2] - b[0]),
        };
        if !on {
            continue;
        }
        for (&t, &w) in points.iter().zip(weights) {
            let (xi, eta) = match side {
                Side::Left => (0.0, t),
                Side::Right => (1.0, t),
                Side::Bottom => (t, 0.0),
                Side::Top => (t, 1.0),
            };
            sum += w * length * f(k, xi, eta, normal);
        }
    }
    sum
}

/// The contact quantities of a solve (module docs): the force Σλᵢ, the length Σℓᵢ over the
/// vertices in contact, the largest pressure λᵢ/ℓᵢ, and with two contact sides each side's
/// force (`contact_force_<side>`, e.g. punch and die of the forming); none before a solve.
pub fn contact(
    state: Option<&CycleState>,
    boundaries: &[ContactBoundary],
    dofs: &DofMap,
) -> Vec<(String, f64)> {
    let Some(state) = state else {
        return Vec::new();
    };
    let (mut length, mut top) = (0.0, 0.0_f64);
    let mut force = vec![0.0; boundaries.len()];
    for load in active_loads(state, boundaries, dofs) {
        force[load.boundary] += load.force;
        length += load.length;
        top = top.max(load.force / load.length);
    }
    let mut out = vec![
        (names::CONTACT_FORCE.to_string(), force.iter().sum()),
        (names::CONTACT_LENGTH.to_string(), length),
        (names::MAX_CONTACT_PRESSURE.to_string(), top),
    ];
    if boundaries.len() > 1 {
        out.extend(
            boundaries
                .iter()
                .zip(force)
                .map(|(b, f)| (format!("contact_force_{}", b.side.name()), f)),
        );
    }
    out
}
