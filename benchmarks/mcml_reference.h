#pragma once
// An in-process reference of MCML's algorithm (Wang, Jacques & Zheng 1995, MCML 1.2.2
// mcmlgo.c: LaunchPhoton, HopDropSpin, Roulette) for bench_photon_mc, so that its ratio to MCML
// is measured in the same run on the same machine, not quoted. Like MCML: double precision, one
// thread, implicit capture (the photon drops w mua/mut at every interaction and always
// scatters), Russian roulette below 1e-4 with CHANCE 0.1, stochastic Fresnel at the surfaces
// (MCML's default, no partial reflection), the absorbed weight binned in (r,z) at the
// interaction point. Unlike MCML: one layer (semi-infinite or a slab), the beam is launched as
// vpsim's (pencil or Gaussian) instead of MCML's pencil plus conv, a tabulated phase function is
// allowed (inverse CDF, for the Mie slurry; MCML has only Henyey-Greenstein), and ran3 is
// replaced by xoshiro256+ (ran3's short period and lattice structure biased MCML's slurry
// results; xoshiro is at least as fast).

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "vpsim/transport/photon_mc.h"

namespace bench {

struct McmlTally {
    std::array<double, vpsim::transport::MC_BATCHES> diffuse{}, within30{}, within84{};
    std::array<uint64_t, vpsim::transport::MC_BATCHES> photons{};
    std::vector<double> absorbedRZ;  ///< [batch][iz * rBins + ir], weight (launched = 1)
    uint64_t interactions = 0;
};

class McmlReference {
public:
    explicit McmlReference(const vpsim::transport::McSetup& s) : mS(s) {
        mMut = s.optics.mua + s.optics.mus;
        mInvMut = 1.0 / mMut;  // reciprocals once, where MCML divides per step
        mInvDr = s.bins.rBins / s.bins.rMax;
        mInvDz = s.bins.zBins / s.bins.zMax;
        double r = (s.nAbove - s.optics.refractiveIndex) / (s.nAbove + s.optics.refractiveIndex);
        mRsp = r * r;
        mState = {0x9E3779B97F4A7C15ull ^ s.seed, 0xBF58476D1CE4E5B9ull, 0x94D049BB133111EBull,
                  0x2545F4914F6CDD1Dull};
        for (int i = 0; i < 16; ++i) next();
    }

    McmlTally run() {
        McmlTally t;
        const size_t bins = size_t(mS.bins.rBins) * mS.bins.zBins;
        t.absorbedRZ.assign(bins * vpsim::transport::MC_BATCHES, 0.0);
        // Photons in consecutive blocks per batch (not i % batches), so that the batch's
        // (r,z) tally stays in cache as in MCML's one array.
        const uint64_t batches = vpsim::transport::MC_BATCHES;
        for (uint64_t i = 0; i < mS.photons; ++i) tracePhoton(size_t(i * batches / mS.photons), t);
        return t;
    }

private:
    static constexpr double WEIGHT = 1e-4, CHANCE = 0.1, COSZERO = 1 - 1e-12;
    static constexpr double PI = 3.14159265358979323846;

    uint64_t next() {  // xoshiro256+
        const uint64_t result = mState[0] + mState[3];
        const uint64_t t = mState[1] << 17;
        mState[2] ^= mState[0];
        mState[3] ^= mState[1];
        mState[1] ^= mState[2];
        mState[0] ^= mState[3];
        mState[2] ^= t;
        mState[3] = (mState[3] << 45) | (mState[3] >> 19);
        return result;
    }
    double rnd() { return (double(next() >> 11) + 0.5) * (1.0 / 9007199254740992.0); }  // (0,1)

    double fresnel(double n1, double n2, double ca1) const {  // MCML RFresnel
        if (n1 == n2) return 0.0;
        if (ca1 > COSZERO) {
            double r = (n2 - n1) / (n2 + n1);
            return r * r;
        }
        if (ca1 < 1e-6) return 1.0;
        double sa1 = std::sqrt(1 - ca1 * ca1);
        double sa2 = n1 * sa1 / n2;
        if (sa2 >= 1.0) return 1.0;
        double ca2 = std::sqrt(1 - sa2 * sa2);
        double cap = ca1 * ca2 - sa1 * sa2, cam = ca1 * ca2 + sa1 * sa2;
        double sap = sa1 * ca2 + ca1 * sa2, sam = sa1 * ca2 - ca1 * sa2;
        return 0.5 * sam * sam * (cam * cam + cap * cap) / (sap * sap * cam * cam);
    }

    double spinTheta() {
        const double g = mS.optics.g;
        if (mS.optics.phase == vpsim::optics::PhaseModel::Tabulated) {
            const auto& table = mS.optics.inverseCdf;
            double x = rnd() * double(table.size() - 1);
            size_t i = std::min(size_t(x), table.size() - 2);
            double f = x - double(i);
            return table[i] * (1 - f) + table[i + 1] * f;
        }
        if (g == 0.0) return 2 * rnd() - 1;
        double temp = (1 - g * g) / (1 - g + 2 * g * rnd());
        double cost = (1 + g * g - temp * temp) * (0.5 / g);
        return cost < -1 ? -1.0 : (cost > 1 ? 1.0 : cost);
    }

    void spin() {  // MCML Spin
        double cost = spinTheta(), sint = std::sqrt(1.0 - cost * cost);
        double psi = 2.0 * PI * rnd();
        double cosp = std::cos(psi),
               sinp = psi < PI ? std::sqrt(1.0 - cosp * cosp) : -std::sqrt(1.0 - cosp * cosp);
        if (std::fabs(mUz) > COSZERO) {
            mUx = sint * cosp;
            mUy = sint * sinp;
            mUz = cost * (mUz >= 0 ? 1.0 : -1.0);
        } else {
            double temp = std::sqrt(1.0 - mUz * mUz), stemp = sint / temp;
            double ux = stemp * (mUx * mUz * cosp - mUy * sinp) + mUx * cost;
            double uy = stemp * (mUy * mUz * cosp + mUx * sinp) + mUy * cost;
            mUz = -sint * cosp * temp + mUz * cost;
            mUx = ux;
            mUy = uy;
        }
    }

    void tracePhoton(size_t batch, McmlTally& t) {
        const size_t bins = size_t(mS.bins.rBins) * mS.bins.zBins;
        double* rz = t.absorbedRZ.data() + batch * bins;
        t.photons[batch] += 1;
        double w = 1.0 - mRsp;
        mX = mY = mZ = 0;
        if (mS.beam == vpsim::transport::BeamShape::Gaussian) {
            double r = mS.w0 * std::sqrt(-0.5 * std::log(rnd())), phi = 2 * PI * rnd();
            mX = r * std::cos(phi);
            mY = r * std::sin(phi);
        }
        mUx = mUy = 0;
        mUz = 1;
        const double n = mS.optics.refractiveIndex, d = mS.thickness;
        for (bool dead = false; !dead;) {
            double s = -std::log(rnd()) * mInvMut;  // StepSizeInTissue
            double toBoundary = 1e300;
            if (mUz < 0)
                toBoundary = -mZ / mUz;
            else if (mUz > 0 && d > 0)
                toBoundary = (d - mZ) / mUz;
            if (s > toBoundary) {  // HitBoundary: hop there and CrossOrNot
                mX += toBoundary * mUx;
                mY += toBoundary * mUy;
                mZ += toBoundary * mUz;
                bool top = mUz < 0;
                double r = fresnel(n, top ? mS.nAbove : mS.nBelow, std::fabs(mUz));
                if (rnd() > r) {
                    if (top) t.diffuse[batch] += w;
                    dead = true;
                } else {
                    mUz = -mUz;
                }
            } else {  // Hop, Drop, Spin
                mX += s * mUx;
                mY += s * mUy;
                mZ += s * mUz;
                ++t.interactions;
                double dwa = w * mS.optics.mua * mInvMut;
                w -= dwa;
                size_t iz = size_t(mZ * mInvDz), ir = size_t(std::sqrt(mX * mX + mY * mY) * mInvDr);
                if (iz < mS.bins.zBins && ir < mS.bins.rBins) rz[iz * mS.bins.rBins + ir] += dwa;
                if (mZ < 0.030) t.within30[batch] += dwa;
                if (mZ < 0.084) t.within84[batch] += dwa;
                spin();
            }
            if (!dead && w < WEIGHT) {  // Roulette
                if (w == 0.0 || rnd() >= CHANCE)
                    dead = true;
                else
                    w /= CHANCE;
            }
        }
    }

    vpsim::transport::McSetup mS;
    double mMut, mInvMut, mInvDr, mInvDz, mRsp;
    std::array<uint64_t, 4> mState;
    double mX = 0, mY = 0, mZ = 0, mUx = 0, mUy = 0, mUz = 1;
};

}  // namespace bench
