//! The directional albedo of the drawn model in the browser: the library's cubature (crates/cubature, the
//! very decisions `vk-render plot albedo` takes) run here, its cells integrated by the page's WebGL2 albedo
//! probe (shaders/web/albedo.frag, the renderer's cell integral). One cubature at a time:
//! [`albedo_start`], then while cells are pending the page reads them at [`albedo_cells`], writes their
//! estimates at [`albedo_estimates`] and calls [`albedo_take`]; then [`albedo_result`].

use std::cell::RefCell;

use cubature::{CellEstimate, Cubature, ALBEDO_TOLERANCE};
use serde_json::{json, Value};

use crate::{answer, input_text};

/// The most outgoing angles one cubature takes (the page asks 19, an environment's table 32).
pub const MAX_ANGLES: usize = 100;

/// Floats per cell in [`albedo_cells`]: two texels of the probe's input (the bounds, then wo).
const CELL_FLOATS: usize = 8;

#[derive(Default)]
struct Session {
    cubature: Option<Cubature>,
    theta_o: Vec<f64>,
    cells: Vec<f32>,
    estimates: Vec<f32>,
}

thread_local! {
    static SESSION: RefCell<Session> = RefCell::new(Session::default());
}

/// Starts a cubature for the input's `length` bytes of JSON, `{"theta_o": [degrees, ...], "tolerance"}`
/// (the tolerance `vk-render plot albedo`'s where left out): answers `{"pending": cells}` or `{"error"}`.
#[no_mangle]
pub extern "C" fn albedo_start(length: usize) -> usize {
    answer(&start(&input_text(length)))
}

/// Where the pending cells are, [`CELL_FLOATS`] floats each: theta_i's bounds, phi_i's, then wo and a 0.
#[no_mangle]
pub extern "C" fn albedo_cells() -> *const f32 {
    SESSION.with_borrow(|session| session.cells.as_ptr())
}

/// Room for `count` cells' estimates, where the page writes them: the Kronrod estimates (RGBA each, as the
/// probe's first target reads back), then the Gauss ones (its second); null when `count` is not the number
/// of cells pending.
#[no_mangle]
pub extern "C" fn albedo_estimates(count: usize) -> *mut f32 {
    SESSION.with_borrow_mut(|session| {
        if count != session.cubature.as_ref().map_or(0, |c| c.pending().len()) {
            return std::ptr::null_mut();
        }
        session.estimates.clear();
        session.estimates.resize(8 * count, 0.0);
        session.estimates.as_mut_ptr()
    })
}

/// Takes the estimates written at [`albedo_estimates`]: answers `{"pending": cells, "rounds"}` (the next
/// round's cells at [`albedo_cells`]) or `{"error"}`.
#[no_mangle]
pub extern "C" fn albedo_take() -> usize {
    answer(&SESSION.with_borrow_mut(take))
}

/// The albedos of the cells integrated so far: `{"theta_o": degrees, "albedo": [[r, g, b], ...], "bound":
/// [...], "rounds"}`, or `{"error"}` when no cubature was started.
#[no_mangle]
pub extern "C" fn albedo_result() -> usize {
    answer(&SESSION.with_borrow(|session| match &session.cubature {
        None => json!({ "error": "no albedo was started" }),
        Some(cubature) => {
            let albedos = cubature.albedos();
            json!({
                "theta_o": session.theta_o,
                "albedo": albedos.iter().map(|a| a.rho).collect::<Vec<_>>(),
                "bound": albedos.iter().map(|a| a.error_bound).collect::<Vec<_>>(),
                "rounds": cubature.rounds(),
            })
        }
    }))
}

/// A cubature of the request's angles started, or why not.
fn start(text: &str) -> Value {
    let request: Value = match serde_json::from_str(text) {
        Ok(request) => request,
        Err(error) => return json!({ "error": format!("the albedo request is no JSON: {error}") }),
    };
    let Some(angles) = request["theta_o"].as_array() else {
        return json!({ "error": "the albedo request has no theta_o list" });
    };
    if angles.is_empty() || angles.len() > MAX_ANGLES {
        return json!({ "error": format!("theta_o has {} angles: from 1 to {MAX_ANGLES}", angles.len()) });
    }
    let mut theta_o = Vec::with_capacity(angles.len());
    for angle in angles {
        match angle.as_f64() {
            Some(degrees) if (0.0..90.0).contains(&degrees) => theta_o.push(degrees),
            _ => return json!({ "error": format!("theta_o {angle}: an angle in degrees from 0 to below 90") }),
        }
    }
    let tolerance = match &request["tolerance"] {
        Value::Null => ALBEDO_TOLERANCE,
        value => match value.as_f64() {
            Some(t) if t > 0.0 && t.is_finite() => t,
            _ => return json!({ "error": format!("tolerance {value}: a positive number") }),
        },
    };
    let radians: Vec<f64> = theta_o.iter().map(|d| d.to_radians()).collect();
    SESSION.with_borrow_mut(|session| {
        session.cubature = Some(Cubature::new(&radians, tolerance));
        session.theta_o = theta_o;
        write_cells(session)
    })
}

fn take(session: &mut Session) -> Value {
    let Some(cubature) = session.cubature.as_mut() else {
        return json!({ "error": "no albedo was started" });
    };
    let count = cubature.pending().len();
    if session.estimates.len() != 8 * count {
        return json!({ "error": format!("{} estimates for {count} cells", session.estimates.len() / 8) });
    }
    let (kronrod, gauss) = session.estimates.split_at(4 * count);
    let rgb = |texel: &[f32]| [texel[0], texel[1], texel[2]];
    let estimates: Vec<CellEstimate> = kronrod
        .chunks_exact(4)
        .zip(gauss.chunks_exact(4))
        .map(|(k, g)| CellEstimate { kronrod: rgb(k), gauss: rgb(g) })
        .collect();
    if let Err((given, pending)) = cubature.take(&estimates) {
        return json!({ "error": format!("{given} estimates for {pending} cells") });
    }
    session.estimates.clear();
    write_cells(session)
}

/// The pending cells written where [`albedo_cells`] says, and how many.
fn write_cells(session: &mut Session) -> Value {
    let Some(cubature) = &session.cubature else {
        return json!({ "error": "no albedo was started" });
    };
    session.cells.clear();
    for cell in cubature.pending() {
        let theta_o = session.theta_o[cell.job].to_radians();
        session.cells.extend([cell.theta.0, cell.theta.1, cell.phi.0, cell.phi.1].map(|v| v as f32));
        session.cells.extend([theta_o.sin() as f32, 0.0, theta_o.cos() as f32, 0.0]);
    }
    debug_assert_eq!(session.cells.len(), CELL_FLOATS * cubature.pending().len());
    json!({ "pending": cubature.pending().len(), "rounds": cubature.rounds() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{input, output};

    fn call(function: extern "C" fn(usize) -> usize, text: &str) -> Value {
        let at = input(text.len());
        unsafe { std::ptr::copy_nonoverlapping(text.as_ptr(), at, text.len()) };
        read_answer(function(text.len()))
    }

    fn read_answer(length: usize) -> Value {
        serde_json::from_slice(unsafe { std::slice::from_raw_parts(output(), length) }).unwrap()
    }

    /// The pending cells, read as the page reads them.
    fn pending_cells(count: usize) -> Vec<f32> {
        unsafe { std::slice::from_raw_parts(albedo_cells(), CELL_FLOATS * count) }.to_vec()
    }

    #[test]
    fn a_lambertian_albedo_is_integrated_from_the_cells_the_page_is_given() {
        let started = call(albedo_start, r#"{"theta_o": [0, 60]}"#);
        let mut count = started["pending"].as_u64().unwrap() as usize;
        assert!(count > 0);
        while count > 0 {
            let cells = pending_cells(count);
            // A probe of Lambert's kd = 0.5 / pi, exact: (sin^2 t1 - sin^2 t0) / 2 * kd * (p1 - p0).
            let mut estimates = vec![0.0f32; 8 * count];
            for (k, cell) in cells.chunks_exact(CELL_FLOATS).enumerate() {
                assert_eq!(cell[5], 0.0, "wo in the xz-plane");
                let exact = (cell[1].sin().powi(2) - cell[0].sin().powi(2)) / 2.0
                    * (0.5 / std::f32::consts::PI)
                    * (cell[3] - cell[2]);
                estimates[4 * k..4 * k + 3].fill(exact);
                estimates[4 * (count + k)..4 * (count + k) + 3].fill(exact);
            }
            let at = albedo_estimates(count);
            assert!(!at.is_null());
            unsafe { std::ptr::copy_nonoverlapping(estimates.as_ptr(), at, estimates.len()) };
            count = read_answer(albedo_take())["pending"].as_u64().unwrap() as usize;
        }
        let result = read_answer(albedo_result());
        assert_eq!(result["theta_o"], json!([0.0, 60.0]));
        for rho in result["albedo"].as_array().unwrap() {
            for channel in rho.as_array().unwrap() {
                assert!((channel.as_f64().unwrap() - 0.5).abs() < 1e-5, "{result}");
            }
        }
        assert_eq!(result["bound"], json!([0.0, 0.0]));
    }

    #[test]
    fn bad_requests_and_estimates_are_refused() {
        assert!(call(albedo_start, "{").get("error").is_some());
        assert!(call(albedo_start, r#"{"theta_o": [90]}"#)["error"].as_str().unwrap().contains("theta_o 90"));
        assert!(call(albedo_start, r#"{"theta_o": []}"#)["error"].as_str().unwrap().contains("0 angles"));
        let many = format!(r#"{{"theta_o": [{}]}}"#, vec!["1"; MAX_ANGLES + 1].join(","));
        assert!(call(albedo_start, &many)["error"].as_str().unwrap().contains("101 angles"));
        assert!(call(albedo_start, r#"{"theta_o": [1], "tolerance": -1}"#)["error"].is_string());
        let pending = call(albedo_start, r#"{"theta_o": [10]}"#)["pending"].as_u64().unwrap() as usize;
        assert!(albedo_estimates(pending + 1).is_null());
        assert!(read_answer(albedo_take())["error"].as_str().unwrap().contains("estimates for"));
    }
}
