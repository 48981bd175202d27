// The stabilized Navier-Stokes system of linear tetrahedra (flow/navier_stokes.h's element),
// worked out for kCellLanes cells at once: each quantity a vector of the cells' values, so that
// the arithmetic is SIMD instructions (AVX2's where the processor has them, chosen when the
// program starts; SSE2's else) on the same IEEE operations, in the same order, as one cell's:
// a cell's system is the same to the bit whatever the cells beside it and the instructions.
// (One cell at a time, the element's arithmetic took half of an assembly's time; the scatter into
// the matrix the other half.)
//
// Per cell, in SI: corners x_a, the advecting velocity u_a and the BDF history h_a at them
// (m/s2: the previous steps' velocities over dt, weighted); its volume V, the shape functions'
// gradients g_a, ubar and hbar the corners' means, the metric G = sum_a g_a g_a^T,
// tau_M = (C_t/dt^2 + ubar.G.ubar + C_I nu^2 G:G)^(-1/2) (C_I = 36; C_t = 4 by default; no time term
// when dt is 0) and tau_C = f_C / (tau_M tr G) (f_C = 1 by default; CellParameters); c_a = ubar . g_a.
// The system in Picard's (Oseen's) form, mass
// coefficient m (alpha0 / dt, 0 for a steady or Stokes system), rows a's momentum (i < 3) and
// continuity (3), columns b's velocity (j < 3) and pressure (3):
//   block(a, b)[i][j] = tau_C V g_a[i] g_b[j] + delta_ij (m M_ab + V/4 c_b + nu V g_a.g_b
//                       + tau_M V c_a (m/4 + c_b))            (Galerkin mass, convection, viscosity; SUPG, LSIC)
//   block(a, b)[i][3] = -V/4 g_a[i] + tau_M V c_a g_b[i]       (the pressure gradient; SUPG)
//   block(a, b)[3][j] = V/4 g_b[j] + tau_M V g_a[j] (m/4 + c_b) (the divergence; PSPG)
//   block(a, b)[3][3] = tau_M V g_a.g_b                          (PSPG)
//   rhs(a)[i] = sum_b M_ab h_b[i] + tau_M V c_a hbar[i],  rhs(a)[3] = tau_M V g_a . hbar
// with the consistent mass M_ab = V/20 (1 + delta_ab); and the Schur complement's preconditioning
// matrix S_ab = w V g_a.g_b, w = V over the cell's momentum diagonal m V + V sum_a ((nu + tau_C/3)
// |g_a|^2 + tau_M c_a^2) (`momentum`; flow/navier_stokes.cpp says why), and the cell's CFL number
// |ubar| dt max_a |g_a|.
#pragma once

namespace vesselmesh::flow {

constexpr int kCellLanes = 4;
constexpr double kCI = 36.0;  // the inverse-estimate constant of linear tetrahedra
// kCellLanes doubles, one a cell (GCC's and Clang's vector extension: element-wise arithmetic).
typedef double CellLanes __attribute__((vector_size(8 * kCellLanes)));

struct CellCorners {
  CellLanes x[4][3];  // m
  CellLanes u[4][3];  // the advecting velocity, m/s
  CellLanes h[4][3];  // the BDF history, m/s2
};

struct CellParameters {
  double mass = 0.0;       // m, 1/s
  double dt = 0.0;         // s; 0: no time term in tau_M, no CFL number
  double viscosity = 0.0;  // kinematic, m2/s
  double time_coefficient = 4.0;  // C_t: tau_M's time term C_t / dt^2 (FlowCase::tau_m_time)
  double tau_c_factor = 1.0;      // tau_C times this (FlowCase::tau_c_factor)
};

struct CellSystems {
  CellLanes volume, g[4][3], ubar[3], hbar[3], tau_m, tau_c, c[4];
  CellLanes cfl, momentum, schur[4][4];
  CellLanes block[4][4][4][4];  // [a][b][i][j]
  CellLanes rhs[4][4];          // [a][i]
};

// The systems of the cells whose corners are given (a lane a cell; unused lanes may hold any
// cell, flat ones give non-finite values there).
void stabilized_cells(const CellCorners& corners, const CellParameters& parameters, CellSystems& out);

}  // namespace vesselmesh::flow
