// Control variates for the diffuse reflectance and transmittance of the analog-transport
// estimators (COLLISION, TRACK). Part of photon_step.glsl (included from it after PhotonTally;
// not used on its own).
//
// A photon's walk is a chain of random stages: a flight (to the next interaction or to a
// surface), at a surface leaving or being reflected, at an interaction being absorbed or not, and
// the scattering angle. For a function phi of the state after a stage whose expectation given the
// state before is known exactly, phi(after) - E[phi(after) | before] has mean zero, whatever phi
// is. Summed over a photon's stages these terms are control variates: subtracting a linear
// combination of their batch means from the reflectance's batch means keeps its expectation and,
// with phi close to the probability of leaving through the top, removes most of its variance
// (the combination is fitted over the control batches, cross-fitted: src/transport/mc_control.cpp).
// The phi used, with e = exp(-kappa z), kappa the diffusion attenuation
// sqrt(3 mua (mua + mus (1 - g))) (clamped to [0.01, 0.5] mut):
//   flight from (z, uz):  [reaches z = 0], the same times 1 - R(uz) (with a refractive step at
//     z = 0, where total internal reflection makes arriving worth little at grazing angles),
//     [reaches z = thickness], e' and uz e' at the next interaction z'. With the chances of
//     reaching the surfaces P0 = exp(-mut z/|uz|) (uz < 0) and P1 = exp(-mut (d - z)/uz) (uz > 0),
//     E[e'] = mut/(mut + kappa uz) (e - P0 - P1 e_d), e_d = exp(-kappa d): the integral of
//     mut exp(-mut s) exp(-kappa (z + uz s)) over the path.
//   at a surface: [leaves], expectation 1 - R (the Fresnel reflectance the step draws against).
//   at an interaction: e and uz e if not absorbed, expectation (1 - mua/mut) times them.
//   scattering: e uz_new, expectation e g uz (the mean cosine g of any phase function rotates
//     uz into g uz on average; for a table, PhotonParams.g is the table's own mean cosine).
// Each term is accumulated in integer units of 2^-32 (exact sums, the same on any thread count
// and on the GPU's atomics).
#ifndef VPSIM_PHOTON_CONTROL
#define VPSIM_PHOTON_CONTROL

// Whether the step accumulates the control variates: asked for, analog transport with estimated
// bins (the plain ANALOG estimator stays the unmodified reference), in a medium that interacts.
bool photonControls(PHOTON_PARAMS_IN p, PHOTON_DERIVED_IN k) {
    uint e = photonEstimator(p);
    return (e == PHOTON_ESTIMATOR_COLLISION || e == PHOTON_ESTIMATOR_TRACK) &&
           (p.estimator & PHOTON_FLAG_CONTROLS) != 0u && k.invMut > float(0);
}

// x in units of 2^-32, truncated towards 0 (at most 2^-32 per term, ~1e-8 per photon), as a
// two's complement word (|x| < 2^31).
uint64_t photonControlQuanta(float x) {
    return uint64_t(int64_t(x * float(4294967296.0)));
}

// The flight stage, after the photon moved from depth z0 (to a surface when boundary). Leaves
// s.depthFactor at e of the interaction reached (0 when the flight ended on a surface).
void photonControlFlight(PHOTON_PARAMS_IN p, PHOTON_DERIVED_IN k, VPSIM_INOUT(PhotonState) s, float z0,
                         bool boundary, VPSIM_INOUT(PhotonTally) t) {
    float uz = s.dir.z;
    float mut = p.mua + p.mus;
    float pTop = uz < float(0) ? photonExp(mut * z0 / uz) : float(0);
    float pBottom = uz > float(0) && p.thickness > float(0) ? photonExp(mut * (z0 - p.thickness) / uz) : float(0);
    float expected = (s.depthFactor - pTop - pBottom * k.controlDepthFactorBottom) /
                     (float(1) + k.controlKappaPath * uz);
    float next = boundary ? float(0) : photonExp(-k.controlKappa * s.pos.z);
    bool top = boundary && uz < float(0);
    t.controls[PHOTON_CONTROL_ARRIVE_TOP] += photonControlQuanta((top ? float(1) : float(0)) - pTop);
    if (uz < float(0) && p.nMedium != p.nAbove) {  // arriving is worth its chance to leave
        float leave = float(1) - photonFresnel(p.nMedium, p.nAbove, -uz);
        t.controls[PHOTON_CONTROL_ARRIVE_TOP_LEAVING] +=
            photonControlQuanta(leave * ((top ? float(1) : float(0)) - pTop));
    }
    if (p.thickness > float(0))
        t.controls[PHOTON_CONTROL_ARRIVE_BOTTOM] +=
            photonControlQuanta((boundary && !top ? float(1) : float(0)) - pBottom);
    t.controls[PHOTON_CONTROL_FLIGHT] += photonControlQuanta(next - expected);
    t.controls[PHOTON_CONTROL_FLIGHT_UZ] += photonControlQuanta(uz * (next - expected));
    s.depthFactor = next;
}

// A photon at a surface (top or bottom) left or was reflected, drawn against reflectance.
void photonControlSurface(PHOTON_DERIVED_IN k, VPSIM_INOUT(PhotonState) s, bool top, bool reflected,
                          float reflectance, VPSIM_INOUT(PhotonTally) t) {
    float left = (reflected ? float(0) : float(1)) - (float(1) - reflectance);
    t.controls[top ? PHOTON_CONTROL_LEAVE_TOP : PHOTON_CONTROL_LEAVE_BOTTOM] += photonControlQuanta(left);
    s.depthFactor = top ? float(1) : k.controlDepthFactorBottom;
}

// The photon at an interaction was absorbed or not (chance k.absorbShare).
void photonControlAbsorption(PHOTON_DERIVED_IN k, PhotonState s, bool absorbed, VPSIM_INOUT(PhotonTally) t) {
    float survived = (absorbed ? float(0) : float(1)) - (float(1) - k.absorbShare);
    t.controls[PHOTON_CONTROL_ABSORB] += photonControlQuanta(s.depthFactor * survived);
    t.controls[PHOTON_CONTROL_ABSORB_UZ] += photonControlQuanta(s.depthFactor * s.dir.z * survived);
}

// The photon scattered from direction cosine uzBefore to s.dir.z.
void photonControlScatter(PHOTON_PARAMS_IN p, PhotonState s, float uzBefore, VPSIM_INOUT(PhotonTally) t) {
    t.controls[PHOTON_CONTROL_SCATTER] += photonControlQuanta(s.depthFactor * (s.dir.z - p.g * uzBefore));
}

#endif
