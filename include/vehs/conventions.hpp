#pragma once
// vehs — the numerical conventions every part of the library relies on, in one place.
//
// Model (dimensionless, as in the seed paper, Eq. 7):
//     dX = Y dt
//     dY = b2(X, Y, t) dt + sqrt(a22(X, Y)) dB(t)            (Itô)
// with
//     b2  = Σ_k c_k φ_k(x, y, u)  + forces of named effects    ("drift")
//     a22 = Σ_m q_m ψ_m(x, y)                                   ("diffusion")
// For the paper's harvester b2 = −βy − Σ k_i x^i and a22 = 2D + 2Q x², so
//     β = −drift["y"],  k_i = −drift["x^i"],  2D = diffusion["1"],  2Q = diffusion["x^2"].
//
// * Itô convention throughout. With noise only on Y and an amplitude depending on X only,
//   Itô and Stratonovich coincide (the Milstein correction vanishes). Velocity-dependent noise
//   (a22 depending on y) is Itô as written; no drift correction is added.
// * a22 is the *variance rate* of dY (units of Y²/time), not a standard deviation; the
//   Fokker–Planck equation therefore carries ½·∂²_y(a22 p).
// * Time is dimensionless; dt in configs is the *recorded* sampling interval. Internal
//   integration steps are dt / substeps.
// * Random numbers: counter-based (Philox-4x32-10), keyed by (seed, record) with the step index
//   as counter, so an ensemble is bit-identical whatever the thread count.
// * Finite-difference grids are cell-centred: n cells over [min, max], centre of cell i at
//   min + (i + ½)·h, h = (max − min)/n. Densities integrate to 1 with the midpoint rule.
// * Term names follow docs/model-file.md: "1", "x", "x^3", "y", "x^2*y", "y^3", "sign(y)",
//   "y*|y|", "u". sign(0) = 0.
//
// Tolerances that are part of the contract:
namespace vehs::conventions {
/// Relative deviation of a time step from its record's interval allowed by default: logged
/// stamps rounded to 6 decimals (3e-4 at 300 Hz), float32 stamps, a software clock jittering by
/// ±0.2 ms at 300 Hz (steps up to 12 % off); a gap is a step of more than 1.5 intervals. The
/// readers' ReadOptions::jitter_tolerance (docs/measurements.md) (a warning above ReadOptions::jitter_warning, 1e-4).
inline constexpr double sampling_jitter_tolerance = 0.15;
/// Relative difference of the intervals of records that must share one (Dataset::common_dt,
/// a config's dt against the files'): their mean steps, each averaged over a whole record.
inline constexpr double record_dt_tolerance = 1e-6;
/// Probability mass allowed on the boundary cells of a user-given FPK domain.
inline constexpr double fpk_boundary_mass_tolerance = 1e-6;
/// Condition number (of the column-equilibrated Gram matrix) above which a dictionary is
/// reported as ill-conditioned instead of being fitted.
inline constexpr double max_gram_condition = 1e12;
}  // namespace vehs::conventions
