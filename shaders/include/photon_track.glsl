// Track-length tally of one flight through the cylindrical (r,z) bins, part of photon_step.glsl
// (included from it after photonPend; not used on its own).
#ifndef VPSIM_PHOTON_TRACK
#define VPSIM_PHOTON_TRACK

// Splits the flight o + t dir, t in [0, len], at the faces of the (r,z) bins and adds
// weight x mua x (length inside) to each bin. r^2(t) = c + 2 b t + a t^2 is smallest at
// t = -b/a: before that the flight may cross the inner cylinder of its bin, after it only the
// outer one. Bin indices are stepped face by face (never recomputed from rounded positions).
// Returns the number of bin pieces visited.
uint photonTrackBins(PHOTON_PARAMS_IN p, PHOTON_DERIVED_IN k, VPSIM_INOUT(PhotonState) s, vec3 o, float len,
                     uint batch) {
    vec3 d = s.dir;
    float scale = float(s.weight) * p.mua;
    float a = d.x * d.x + d.y * d.y;
    float b = o.x * d.x + o.y * d.y;
    float c = o.x * o.x + o.y * o.y;
    int nr = int(p.rBins), nz = int(p.zBins);
    int ir = int(min(sqrt(c) * k.invRBinWidth, float(nr)));  // nr: beyond the grid radially
    int iz = int(min(max(o.z, float(0)) * k.invZBinWidth, float(nz)));
    bool radial = a > float(1.0e-12);
    float invA = radial ? float(1) / a : float(0);
    float invDz = d.z != float(0) ? float(1) / d.z : float(0);
    float tTurn = radial ? -b * invA : PHOTON_FAR;
    float t = float(0);
    // The next z face and the next cylinder are recomputed only when their index steps: a
    // crossing found before the turning point stays the next one until it is passed.
    float tz = PHOTON_FAR, tr = PHOTON_FAR;
    int stepR = 0;
    bool newZ = true, newR = true;
    for (int guard = 0; guard < 2 * (nr + nz) + 8; ++guard) {
        if (newZ) {
            tz = PHOTON_FAR;
            if (d.z > float(0) && iz < nz) tz = (float(iz + 1) * p.zBinWidth - o.z) * invDz;
            else if (d.z < float(0)) tz = (float(min(iz, nz)) * p.zBinWidth - o.z) * invDz;
        }
        if (newR) {
            tr = PHOTON_FAR;
            stepR = 0;
            if (radial && t < tTurn && ir > 0) {  // heading inwards: the inner cylinder, if reached
                float rr = float(ir) * p.rBinWidth;
                float disc = b * b - a * (c - rr * rr);
                if (disc >= float(0)) {
                    tr = (-b - sqrt(disc)) * invA;
                    stepR = -1;
                }
            }
            if (radial && stepR == 0 && ir < nr) {  // the outer cylinder
                float rr = float(ir + 1) * p.rBinWidth;
                tr = (-b + sqrt(max(b * b - a * (c - rr * rr), float(0)))) * invA;
                stepR = 1;
            }
        }
        float next = max(min(min(tz, tr), len), t);
        photonPend(s, batch, ir < nr && iz < nz ? iz * nr + ir : -1, scale * (next - t));
        if (next >= len) return uint(guard + 1);
        newZ = tz <= tr;
        newR = !newZ;
        if (newZ) iz += d.z > float(0) ? 1 : -1;
        else ir += stepR;
        t = next;
        if (iz < 0 || (iz >= nz && d.z >= float(0)) || (ir >= nr && t >= tTurn)) return uint(guard + 1);
    }
    return uint(2 * (nr + nz) + 8);
}

#endif
