/* Choices of the general tensor path (Hoover, Hoover & Merritt, PRE 69, 016702 (2004);
 * equations as corrected in docs/equations.md). Every combination of the PRE
 * study space is one value of this struct. */
#ifndef SPAM_SOLID_H
#define SPAM_SOLID_H
#include <petscsys.h>

typedef enum { SPAM_DENSITY_SUMMATION, SPAM_DENSITY_CONTINUITY, SPAM_DENSITY_CHAIN_RULE } SpamDensityMode;
typedef enum { SPAM_DENSITY_INITIAL_IDEAL, SPAM_DENSITY_INITIAL_SUMMED } SpamDensityInitial;
typedef enum { SPAM_COORDS_R0, SPAM_COORDS_R1, SPAM_COORDS_R2 } SpamCoordsMode;
typedef enum { SPAM_MATERIAL_ELASTIC, SPAM_MATERIAL_GAS, SPAM_MATERIAL_ISENTROPE } SpamMaterial;
typedef enum { SPAM_VISCOSITY_NONE, SPAM_VISCOSITY_MONAGHAN, SPAM_VISCOSITY_VON_NEUMANN } SpamViscosityMode;
typedef enum { SPAM_ANGMOM_NONE, SPAM_ANGMOM_GAUSS, SPAM_ANGMOM_TI, SPAM_ANGMOM_TIJ } SpamAngmomMode;
/* The gas's pair scheme: the papers' plain equations, or the flowing-fluid scheme of
 * gas_flow.c (background pressure out of the momentum equation, transport shifting). */
typedef enum { SPAM_GAS_PLAIN, SPAM_GAS_FLOW } SpamGasScheme;
typedef enum { SPAM_BACKGROUND_NONE, SPAM_BACKGROUND_MEAN } SpamBackgroundMode;
/* How viscosity and conduction reach the pair force: through the particles' gradients
 * (the papers' two passes) or as pair Laplacians in one pass (gas_flow.h). */
typedef enum { SPAM_DIFFUSION_GRADIENT, SPAM_DIFFUSION_PAIR } SpamDiffusionForm;
/* The kernel range: one h for every particle, or each particle's own h_i from
 * rho_i h_i^D = eta^D m_i with the grad-h terms (smoothing_adaptive.c, rhs_gas_adaptive.c). */
typedef enum { SPAM_SMOOTHING_FIXED, SPAM_SMOOTHING_ADAPTIVE, SPAM_SMOOTHING_EVOLVED } SpamSmoothingMode;
/* Where the flow scheme's background pressure works on the shift's compression
 * (-shift_compression, gas_flow.c): nowhere, where the background varies along gravity and
 * no no-slip wall moves (the default), or in every flow-scheme run with a summed density. */
typedef enum { SPAM_SHIFT_WORK_OFF, SPAM_SHIFT_WORK_STRATIFIED, SPAM_SHIFT_WORK_ALL } SpamShiftWork;

extern const char *const SpamDensityModeNames[];
extern const char *const SpamDensityInitialNames[];
extern const char *const SpamCoordsModeNames[];
extern const char *const SpamAngmomModeNames[];
extern const char *const SpamViscosityModeNames[];
extern const char *const SpamMaterialNames[];
extern const char *const SpamGasSchemeNames[];
extern const char *const SpamBackgroundModeNames[];
extern const char *const SpamDiffusionFormNames[];
extern const char *const SpamSmoothingModeNames[];
extern const char *const SpamShiftWorkNames[]; /* "false", "stratified", "true" */
/* -h_tol's default: Newton's last step then moved h_i by about 1e-11 of itself, far below
 * the integrators' tolerances, so the right-hand side is smooth to that level. */
#define SPAM_H_TOL_DEFAULT 1e-10

typedef struct {
  SpamMaterial       material;      /* elastic (stress in the state), ideal gas with  */
                                    /* the energy equation, or the isentropic gas     */
  double             gamma, gas_e0; /* gas: P = (gamma - 1) rho e; initial e            */
  double             shear_visc, bulk_visc; /* Newtonian viscosity (0: off)             */
  double             conductivity;  /* Fourier heat conduction kappa (0: off)          */
  double             lambda, eta;   /* Lame constants of Hooke's law                   */
  double             rho0;          /* stress-free (ideal lattice) density             */
  SpamDensityMode    density;
  SpamDensityInitial density_initial;
  PetscBool          rho_geometric; /* rho_ij = sqrt(rho_i rho_j), else the mean       */
  SpamCoordsMode     coords;
  double             xsph_eps;      /* epsilon of R2                                   */
  SpamAngmomMode     angmom;
  PetscBool          per_body;      /* torque scaling per connected body, else global  */
  SpamViscosityMode  viscosity;     /* artificial viscosity                            */
  double             visc_alpha, visc_beta; /* its linear and quadratic coefficients   */
  double             sound_speed;   /* c of the linear term: c_L at rho0 (set-up)      */
  double             closest_approach; /* reflect approaching pairs nearer (0: off)  */
  SpamGasScheme      scheme;        /* gas: plain or flow (gas_flow.c)                 */
  SpamBackgroundMode background;    /* flow: pressure taken out of the momentum eq.   */
  double             shift_coef;    /* flow: transport shifting coefficient (0: off)  */
  SpamDiffusionForm  diffusion;     /* flow: viscosity and conduction's pair form     */
  PetscBool          heat_linear;   /* flow, pair form: conduction exact for linear T  */
                                    /* on any arrangement (pair_diffusion.h)           */
  SpamShiftWork      shift_work;    /* flow: where B's compression work follows the   */
                                    /* shift's change of the summed density too (gas_flow.c) */
  PetscBool          plain_default; /* the scene's gas keeps the plain scheme unless  */
                                    /* asked (gas_flow.h: expansion into vacuum, and  */
                                    /* the convection cell, whose onset it moves)      */
  SpamSmoothingMode  smoothing;     /* fixed h, or h_i solved (adaptive) or integrated (evolved) (gas) */
  double             h_eta;         /* adaptive: h_i / (m_i/rho_i)^(1/D); 0: -h        */
  double             h_min, h_max;  /* adaptive: bounds of h_i, as factors of -h       */
  double             h_tol;         /* adaptive: |rho h^D/(eta^D m) - 1| of a settled h_i */
} SpamSolidParams;

/* The flow scheme's default transport shifting coefficient (gas_flow.c). */
#define SPAM_SHIFT_COEF_DEFAULT 0.1

/* Reads the -solid_*, -density*, -coordinates, -xsph_eps and -angmom* options (with
 * -help lists them with their defaults) into p, whose fields hold the defaults. */
PetscErrorCode SpamSolidOptions(SpamSolidParams *p);
/* -smoothing_length and, when adaptive, -h_eta, -h_min and -h_max, inside the options
 * block of SpamSolidOptions (all of them with help); SpamSmoothingValidate checks them. */
PetscErrorCode SpamSmoothingOptions(PetscOptionItems *PetscOptionsObject, PetscBool help, const char *mat, SpamSolidParams *p, char *mode, size_t len);
PetscErrorCode SpamSmoothingValidate(const char *mode, SpamSolidParams *p);
#endif
