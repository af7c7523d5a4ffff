//! Friction: tangential collisions built from the normal collisions at the lagged positions,
//! and the smooth friction dissipative potential over them, as the IPC toolkit 1.6 defines
//! them (`TangentialCollisions`, `FrictionPotential`).
//!
//! Each tangential collision keeps, from the lagged positions: its stencil's vertices, the
//! closest-point coordinates ([`closest_point`](self#functions)), the tangent basis, the
//! normal force magnitude of the normal potential, the normal collision's weight and the
//! static and kinetic coefficients. The potential is then a function of the velocities `v`:
//! `D(v) = sum_k w_k N_k g0(|P_k^T Γ_k v|)`, with `g0` the mollified friction profile of
//! [`smooth_mu_f0`] (threshold `eps_v`, in velocity units).

mod closest_point;
mod error;
mod mollifier;
mod potential;
mod relative_velocity;
mod tangent_basis;
mod tangential_collisions;

pub use closest_point::{
    edge_edge_closest_point, point_edge_closest_point, point_triangle_closest_point,
};
pub use error::FrictionError;
pub use mollifier::{
    smooth_friction_f0, smooth_friction_f1, smooth_friction_f1_over_x, smooth_friction_f2,
    smooth_friction_f2_x_minus_f1_over_x3, smooth_mu, smooth_mu_derivative, smooth_mu_f0,
    smooth_mu_f1, smooth_mu_f1_over_x, smooth_mu_f2, smooth_mu_f2_x_minus_mu_f1_over_x3,
};
pub use potential::FrictionPotential;
pub use relative_velocity::{
    edge_edge_relative_velocity_jacobian, jacobian_matrix, point_edge_relative_velocity_jacobian,
    point_point_relative_velocity_jacobian, point_triangle_relative_velocity_jacobian,
    relative_velocity,
};
pub use tangent_basis::{
    edge_edge_tangent_basis, point_edge_tangent_basis, point_point_tangent_basis,
    point_triangle_tangent_basis,
};
pub use tangential_collisions::{
    FrictionCoefficients, NormalStencil, StencilKind, TangentialCollision, TangentialCollisions,
};

#[cfg(test)]
mod tests;
