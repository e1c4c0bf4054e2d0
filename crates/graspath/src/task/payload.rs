//! The carried object as a payload: its mass properties from the task file (a mass or a
//! density, the shape's centroid and inertia, or a given centre of mass), and each arm's
//! dynamics model with the world's gravity in the arm's base frame.

use super::file::ObjectFile;
use super::sealed::ArmSetup;
use crate::manipulability::IndexMeasure;
use crate::robot::{Chain, Dynamics, RigidBody, STANDARD_GRAVITY};
use nalgebra::{Isometry3, Matrix3, Vector3};
use std::sync::Arc;

/// The largest object mass accepted (kg): more is a unit mistake (grams given as kilograms),
/// not a payload for a manipulator.
pub const MAX_PAYLOAD_MASS: f64 = 1000.0;

/// The largest distance of the object's centre of mass from its frame's origin (m): more is a
/// unit mistake (millimetres given as metres).
pub const MAX_CENTER_OF_MASS_DISTANCE: f64 = 10.0;

/// The object's mass properties from its task-file fields (object frame), `None` without a
/// mass or a density. Errors name the field: `(field, message)`.
pub(super) fn object_payload(object: &ObjectFile) -> Result<Option<RigidBody>, (String, String)> {
    let err = |field: &str, message: String| Err((format!("object.{field}"), message));
    let center = match object.center_of_mass {
        Some(c) if c.iter().any(|v| !v.is_finite()) => {
            return err("center_of_mass", format!("{c:?} is not finite"))
        }
        Some(c) => Some(Vector3::from(c)),
        None => None,
    };
    let solid = match &object.shape {
        Some(shape) if object.mass.is_some() || object.density.is_some() => {
            Some(shape.solid_mass().map_err(|e| {
                (
                    "object.shape".to_string(),
                    format!("{e} (the object's mass properties need a solid)"),
                )
            })?)
        }
        _ => None,
    };
    let (mass, inertia) = match (object.mass, object.density, &solid) {
        (None, None, _) => {
            return match center {
                Some(_) => err(
                    "center_of_mass",
                    "give the object's mass (or density) with its centre of mass".into(),
                ),
                None => Ok(None),
            };
        }
        (Some(_), Some(_), _) => return err("density", "give mass or density, not both".into()),
        (None, Some(_), None) => {
            return err(
                "density",
                "a density needs the object's shape (its volume); give mass instead".into(),
            )
        }
        (Some(mass), None, solid) => (mass, solid.map(|s| s.inertia_for_mass(mass))),
        (None, Some(density), Some(solid)) => {
            if !(density > 0.0 && density.is_finite()) {
                return err(
                    "density",
                    format!("must be a positive finite density in kg/m³, got {density}"),
                );
            }
            (density * solid.volume, Some(solid.inertia * density))
        }
    };
    let field = if object.mass.is_some() {
        "mass"
    } else {
        "density"
    };
    if !(mass > 0.0 && mass.is_finite()) {
        return err(
            field,
            format!("the object's mass must be positive and finite (kg), got {mass}"),
        );
    }
    if mass > MAX_PAYLOAD_MASS {
        return err(
            field,
            format!(
                "the object's mass would be {mass} kg, more than {MAX_PAYLOAD_MASS} kg: is it \
                 in grams (mass) or g/cm³ (density)? Give kilograms (kg/m³)"
            ),
        );
    }
    let com = match (center, &solid) {
        (Some(c), _) => c,
        (None, Some(solid)) => solid.centroid,
        (None, None) => {
            return err(
                "center_of_mass",
                "an object without a shape needs its centre of mass with its mass (object \
                 frame, m)"
                    .into(),
            )
        }
    };
    if com.norm() > MAX_CENTER_OF_MASS_DISTANCE {
        return err(
            "center_of_mass",
            format!(
                "is {:.3} m from the object's origin, more than {MAX_CENTER_OF_MASS_DISTANCE} \
                 m: is it in millimetres? Give metres",
                com.norm()
            ),
        );
    }
    Ok(Some(RigidBody::new(
        mass,
        com,
        inertia.unwrap_or_else(Matrix3::zeros),
    )))
}

/// Gives each arm the dynamics model the task needs: with a payload (`object.mass`) the
/// joint torques along the motion, and with `index.measure: dynamic` the torque-weighted
/// index, which also needs an effort limit on every joint. Errors name the field that asked.
pub(super) fn attach_dynamics(
    arms: &mut [ArmSetup],
    payload: Option<&RigidBody>,
    measure: IndexMeasure,
) -> Result<(), (&'static str, String)> {
    if let Some(payload) = payload {
        check_payload(payload).map_err(|m| ("object.mass", m))?;
        for arm in arms.iter_mut() {
            let model = arm_dynamics(
                &arm.name,
                &arm.chain,
                &arm.world_from_base,
                "the object's mass asks for the joint torques along the task",
            )
            .map_err(|m| ("object.mass", m))?;
            arm.dynamics = Some(Arc::new(model));
        }
    }
    if measure == IndexMeasure::Dynamic {
        for arm in arms.iter_mut() {
            let why = "index.measure dynamic weighs the joints by their torques";
            if arm.dynamics.is_none() {
                let model = arm_dynamics(&arm.name, &arm.chain, &arm.world_from_base, why)
                    .map_err(|m| ("index.measure", m))?;
                arm.dynamics = Some(Arc::new(model));
            }
            let unlimited = arm
                .chain
                .motion_limits()
                .iter()
                .zip(arm.chain.joint_names())
                .find(|(l, _)| !l.effort.is_some_and(|e| e.is_finite() && e > 0.0));
            if let Some((_, joint)) = unlimited {
                return Err((
                    "index.measure",
                    format!(
                        "arm '{}': joint '{joint}' has no effort limit; {why}",
                        arm.name
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Checks a payload given to the task builder: a valid body of positive mass.
pub(super) fn check_payload(body: &RigidBody) -> Result<(), String> {
    if !body.is_valid() || body.mass <= 0.0 {
        return Err(format!(
            "the payload must have a positive finite mass, a finite centre of mass and a \
             symmetric inertia with a non-negative diagonal, got {body:?}"
        ));
    }
    if body.mass > MAX_PAYLOAD_MASS || body.com.norm() > MAX_CENTER_OF_MASS_DISTANCE {
        return Err(format!(
            "the payload's mass ({} kg) or centre of mass ({:.3} m from the object's origin) \
             is out of range (at most {MAX_PAYLOAD_MASS} kg, {MAX_CENTER_OF_MASS_DISTANCE} m): \
             check the units",
            body.mass,
            body.com.norm()
        ));
    }
    Ok(())
}

/// The dynamics model of arm `name` (`chain`, its base at `world_from_base`) with the world's
/// gravity (9.81 m/s² along the world's −z) in the arm's base frame; `why` (e.g. "the object's
/// mass asks for the joint torques along the task") ends the message when it cannot be built.
pub(super) fn arm_dynamics(
    name: &str,
    chain: &Chain,
    world_from_base: &Isometry3<f64>,
    why: &str,
) -> Result<Dynamics, String> {
    let gravity = world_from_base.inverse().rotation * Vector3::new(0.0, 0.0, -STANDARD_GRAVITY);
    chain
        .dynamics()
        .and_then(|d| d.with_gravity(gravity))
        .map_err(|e| format!("arm '{name}': {e}; {why}"))
}
