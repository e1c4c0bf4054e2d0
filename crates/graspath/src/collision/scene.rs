//! The world around the robot: a table and named obstacles, fixed in the world frame.

use super::body::{Body, Table};
use super::CollisionError;
use crate::geometry::shape::Shape;
use nalgebra::Isometry3;

/// An obstacle: a body fixed in the world.
#[derive(Debug, Clone)]
pub struct Obstacle {
    /// The body (its name is `obstacle NAME`).
    pub body: Body,
    /// Its pose `world_from_body` (m).
    pub world_from_body: Isometry3<f64>,
}

/// A table and obstacles, world frame (m). The empty scene has neither.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    table: Option<Table>,
    obstacles: Vec<Obstacle>,
    /// The bodies in the order checks visit them: the table first, then the obstacles.
    bodies: Vec<(Body, Isometry3<f64>)>,
}

/// The thickness of a table given with a footprint, when none is given (m).
pub const DEFAULT_TABLE_THICKNESS: f64 = 0.05;

impl Scene {
    /// The empty scene.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a table whose top surface is at world `z = height` (m): an infinite plane without a
    /// `footprint`, else a slab of size `[x, y]` centred at `[x, y]` and `thickness` thick.
    pub fn with_table(
        mut self,
        height: f64,
        footprint: Option<([f64; 2], [f64; 2])>,
        thickness: Option<f64>,
    ) -> Result<Self, CollisionError> {
        let bad = |field: &str, message: String| CollisionError::BadBody {
            what: format!("table.{field}"),
            message,
        };
        if !height.is_finite() {
            return Err(bad("height", format!("must be finite, got {height}")));
        }
        let thickness = thickness.unwrap_or(DEFAULT_TABLE_THICKNESS);
        if !(thickness.is_finite() && thickness > 0.0) {
            return Err(bad(
                "thickness",
                format!("must be a positive finite length in metres, got {thickness}"),
            ));
        }
        if let Some((size, centre)) = footprint {
            for (k, v) in size.iter().enumerate() {
                if !(v.is_finite() && *v > 0.0) {
                    return Err(bad(
                        &format!("size[{k}]"),
                        format!("must be a positive finite length in metres, got {v}"),
                    ));
                }
            }
            for (k, v) in centre.iter().enumerate() {
                if !v.is_finite() {
                    return Err(bad(
                        &format!("centre[{k}]"),
                        format!("must be finite, got {v}"),
                    ));
                }
            }
        }
        let table = Table {
            height,
            footprint,
            thickness,
        };
        self.bodies.insert(0, table.body());
        self.table = Some(table);
        Ok(self)
    }

    /// Adds an obstacle of `shape` at `world_from_shape`, named `name` in messages.
    pub fn with_shape(
        mut self,
        name: &str,
        shape: &Shape,
        world_from_shape: Isometry3<f64>,
    ) -> Self {
        self.push(
            Body::from_shape(format!("obstacle {name}"), shape),
            world_from_shape,
        );
        self
    }

    /// Adds an obstacle body (a mesh surface, a cloud of spheres, ...) at `world_from_body`.
    pub fn with_body(mut self, body: Body, world_from_body: Isometry3<f64>) -> Self {
        self.push(body, world_from_body);
        self
    }

    fn push(&mut self, body: Body, world_from_body: Isometry3<f64>) {
        self.obstacles.push(Obstacle {
            body: body.clone(),
            world_from_body,
        });
        self.bodies.push((body, world_from_body));
    }

    /// The table, if any.
    pub fn table(&self) -> Option<&Table> {
        self.table.as_ref()
    }

    /// The obstacles, in the order added.
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles
    }

    /// Every body of the scene with its pose: the table first, then the obstacles.
    pub fn bodies(&self) -> &[(Body, Isometry3<f64>)] {
        &self.bodies
    }

    /// Whether the scene has no table and no obstacle.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }
}
