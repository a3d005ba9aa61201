//! The charts of the studies, built from their values: what `vk-render plot` writes and the server's explore
//! page shows beside its picture are one chart.

use glam::Vec3;

use super::albedo::Albedo;
use super::lobe::LobeCut;
use super::{angle_table, describe, rgb, Channel, NamedBrdf};
use crate::pictures::chart::{value_range, LineChart, LobeChart, Series, PALETTE};

/// How a lobe chart shows its values.
#[derive(Clone, Copy, Debug)]
pub struct LobeStyle {
    /// The channel the curves show.
    pub channel: Channel,
    /// log10(1 + value) rather than the value.
    pub log: bool,
}

/// The lobe chart of `materials` over `cuts` (one incidence angle each, all with the same phi and cosine):
/// `values[k][m]` is material m's lobe along cut k at [`super::lobe::lobe_angles`].
pub fn lobe_chart(
    materials: &[NamedBrdf],
    cuts: &[LobeCut],
    angles: &[f64],
    values: &[Vec<Vec<Vec3>>],
    style: LobeStyle,
) -> LobeChart {
    let mut series = Vec::new();
    let mut incident = Vec::new();
    for (k, (cut, values)) in cuts.iter().zip(values).enumerate() {
        for (m, (material, lobe)) in materials.iter().zip(values).enumerate() {
            let colour = PALETTE[(k * materials.len() + m) % PALETTE.len()];
            if m == 0 {
                incident.push((cut.theta_i, colour));
            }
            let shown = |v: f64| if style.log { (1.0 + v).log10() } else { v };
            series.push(Series {
                label: format!("{}: {}, θi {}°", material.name, describe(&material.brdf), cut.theta_i),
                colour,
                points: angles.iter().zip(lobe).map(|(&a, f)| (a, shown(style.channel.of(rgb(*f))))).collect(),
                dashed: false,
            });
        }
    }
    let (phi, cosine) = cuts.first().map_or((0.0, true), |c| (c.phi, c.cosine));
    let quantity = if cosine { "f_r cos θo" } else { "f_r" };
    let plane = if phi == 0.0 { "plane of incidence".to_string() } else { format!("cut at φ = {phi}°") };
    let quantity = if style.log { format!("log10(1 + {quantity})") } else { quantity.to_string() };
    LobeChart {
        title: format!("Lobes: {quantity}, {plane}, {}", style.channel.name()),
        quantity: format!("{quantity} ({})", style.channel.name()),
        series,
        incident,
    }
}

/// The directional albedo chart of `materials`: `curves[m]` is material m's albedo at `angles` (degrees),
/// each within `bound`.
pub fn albedo_chart(
    materials: &[NamedBrdf],
    angles: &[f64],
    curves: &[Vec<Albedo>],
    bound: f64,
    channel: Channel,
) -> LineChart {
    let series: Vec<Series> = materials
        .iter()
        .zip(curves)
        .enumerate()
        .map(|(k, (material, curve))| Series {
            label: format!("{}: {}", material.name, describe(&material.brdf)),
            colour: PALETTE[k % PALETTE.len()],
            points: angles.iter().zip(curve).map(|(&a, albedo)| (a, channel.of(albedo.rho))).collect(),
            dashed: false,
        })
        .collect();
    let y_range = value_range(series.iter().flat_map(|s| s.points.iter().map(|p| &p.1)).chain([&1.0]));
    LineChart {
        title: format!("Directional albedo ρ(θo) = ∫ f_r cos θi dωi ({}, error ≤ {bound:.0e})", channel.name()),
        x_label: "θo (degrees)".into(),
        y_label: format!("ρ ({})", channel.name()),
        x_range: (0.0, 90.0),
        y_range,
        series,
        horizontal_rules: vec![1.0],
        size: (1100, 620),
    }
}

/// A lobe as `vk-render plot lobe` writes its CSV: theta_o, then three columns per material (`lobes[m]` at
/// `angles`).
pub fn lobe_table(materials: &[NamedBrdf], angles: &[f64], lobes: &[Vec<Vec3>]) -> String {
    let columns: Vec<_> = materials
        .iter()
        .zip(lobes)
        .map(|(m, lobe)| (m.name.clone(), lobe.iter().copied().map(rgb).collect()))
        .collect();
    angle_table("theta_o", angles, &columns)
}

/// Directional albedos as `vk-render plot albedo` writes its CSV: theta_o, then three columns per material.
pub fn albedo_table(materials: &[NamedBrdf], angles: &[f64], curves: &[Vec<Albedo>]) -> String {
    let columns: Vec<_> = materials
        .iter()
        .map(|m| m.name.clone())
        .zip(curves.iter().map(|c| c.iter().map(|a| a.rho).collect()))
        .collect();
    angle_table("theta_o", angles, &columns)
}
