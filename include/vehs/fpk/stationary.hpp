#pragma once
// Stationary Fokker–Planck equation of the harvester model on a finite-difference grid.
//
// Equation (Itô, conventions.hpp; a22 is the variance rate, hence the ½):
//     0 = −∂x(y p) − ∂y(b2 p) + ½ ∂²y(a22 p),      ∫∫ p dx dy = 1,
// for dX = Y dt, dY = b2(X, Y) dt + sqrt(a22(X, Y)) dB. b2 may hold every drift term a model
// file can hold except the recorded drive `u` (monomials x^a·y^b, sign(y), y·|y|) plus the
// x-only force of the `impact_stop` effect; a22 may hold monomials in x and y. Effects that
// make (X, Y) non-Markov or time-dependent (harmonic_forcing, electromechanical_coupling,
// colored_noise) have no stationary 2-D FPK and are rejected.
//
// Grid: cell-centred (conventions.hpp): nx × ny cells over [x.min, x.max] × [y.min, y.max];
// unknown p_k is the density at the centre of cell (i, j), k = i·ny + j; integrals use the
// midpoint rule. All schemes are second order in h (observed order 2.0 on the exact Q = 0 test):
//  * Scheme::Flux (default) — conservative finite volumes. Face fluxes
//        Jx(i+½, j) = y_j·p(i+½, j),   p(i+½) = (−p_i−1 + 7p_i + 7p_i+1 − p_i+2)/12
//                     (fourth-order interpolation; (p_i + p_i+1)/2 on the faces next to the
//                     outer ones, where the density is negligible),
//        Jy(i, j+½) = b2(x_i, y_j+½)·(p_ij + p_i,j+1)/2 − (a22_i,j+1·p_i,j+1 − a22_ij·p_ij)/(2 hy),
//    zero flux through the outer faces. Every column of the matrix sums to zero (up to
//    rounding), so total mass is conserved exactly and the equation dropped for the
//    normalisation row is implied by the others (its residual is reported as a check).
//    Why this default: x is pure advection (no diffusion) and the wells are narrow in x, so the
//    x-flux error dominates; the fourth-order x-flux cuts the L1 error 4× at 400² (1.3e-4 vs
//    5.2e-4) for about 2× the factorisation cost — cheaper than the 800² grid flux2 needs for
//    the same accuracy (8× the cost). The y-error stays O(h²), hence observed order 2.
//    Central fluxes are not monotone: on grids that do not resolve the density they undershoot
//    (SolveSummary::negative_mass); first-order upwinding would avoid it at the price of a
//    visible bias, and exponential fitting in y (Scharfetter–Gummel) was tried and rejected:
//    its O(z²) artificial diffusion (z = 2 b2 h / a22 ≈ 1 here) gave 2e-2 L1 at 400².
//    The direct solver does not factorise this 7-point operator by default: it factorises the
//    compact flux2 operator and applies two defect-correction steps (SolveOptions::
//    correction_steps; measured at 400²: L1 1.326e-4 after one step, 1.312e-4 after two, the
//    same as the exact solve of the 7-point system). On unresolved grids (≲ 100² here) the
//    correction can amplify grid-scale modes; the undershoot check reports that.
//  * Scheme::Flux2 — the same with (p_i + p_i+1)/2 in x: compact 5-point stencil, fastest.
//  * Scheme::Central — the paper's Eq. 35 with the *correct* central differences
//    (p_i+1 − p_i−1)/(2h) applied to the expanded (non-conservative) Eq. 32,
//        −y ∂x p − (∂y b2) p − b2 ∂y p + ½ a22 ∂²y p + (∂y a22) ∂y p + ½ (∂²y a22) p = 0,
//    with p = 0 outside the grid (the paper states no boundary condition). Not conservative:
//    the dropped equation's residual is O(h²), not zero. Cannot represent sign(y) (its
//    y-derivative is a delta) and rejects it.
//  * Scheme::PaperLiteral — Eq. 35 exactly as printed, first derivatives (p_i+1 − p_i−1)/h
//    without the factor ½. This doubles the advection terms (in x and y) relative to the
//    diffusion and to the zeroth-order (∂y b2)·p term: an inconsistent scheme, kept only to show
//    what the misprint does (L1 error > 0.05 that does not shrink with h, see the tests).
//
// Solvers:
//  * Solver::Direct — sparse LU (SuiteSparse UMFPACK, symmetric strategy, METIS or AMD
//    ordering) of the singular system
//    made regular by replacing the equation of one cell r (the density maximum; first guessed
//    at the deepest well of the potential at y ≈ 0, moved and re-solved if the guess holds
//    less than 1 % of the maximum) by s·p_r = s, s = mean |diagonal|; then p is normalised to
//    ∫p = 1 with the midpoint rule. The row keeps its pattern (explicit zeros) so that sweeps
//    can reuse one symbolic factorisation.
//  * Solver::Sor — the paper's iteration (Eq. 37): Gauss–Seidel sweeps in the paper's order
//    (x index fastest) relaxed by alpha, negative values set to 0, normalisation every
//    `normalize_every` sweeps, stopped when max|p_new − p_old| / max p < tolerance. With
//    alpha = 0.01 the change per sweep is ~alpha × the error, so the rule either fires far
//    from the solution or never (the paper's own 50² case: not after 10⁶ sweeps); the summary
//    reports the true residual so that this is visible.
//  * Solver::Bicgstab — BiCGSTAB with an incomplete-LU (ILUT) preconditioner on the same
//    bordered system, for grids too large to factorise; stops at a relative residual of
//    `iterative.tolerance`.
//
// Tolerances: the contract allows at most conventions::fpk_boundary_mass_tolerance (1e-6) of
// the mass in the outermost ring of cells of a user-given domain; `boundary_mass_tolerance`
// can raise it explicitly (e.g. to reproduce the paper's [−1.6, 1.6]² grid).
#include "vehs/fpk/assemble.hpp"
#include "vehs/fpk/fpk_model.hpp"
#include "vehs/fpk/grid.hpp"
#include "vehs/fpk/solve.hpp"
#include "vehs/fpk/sweep.hpp"
