// Photon Monte Carlo efficiency measured fairly (issue 14): for seed 000's alumina slurry and a
// slurry-like HG medium (mus 3030/cm, mua 84/cm, g 0.9, n 1), Gaussian beam W0 = 50 um,
// semi-infinite, the figure of merit FOM = 1 / (sigma^2 t) of
//   - the diffuse reflectance, the fraction absorbed within 30 um and within 84 um,
//   - the kernel's (r,z) bins at the cure front (depths De3D..3 De3D, r < We3D; sigma^2 is the
//     mean relative variance of those bins),
// for each estimator (analog, collision, track-length, implicit, implicit-track) and for an
// in-process reference of MCML's algorithm (benchmarks/mcml_reference.h: implicit capture, roulette
// at 1e-4, double precision, one thread), all in the same run (the default estimator, the analog
// one and the reference back to back, since the machine's speed drifts). sigma comes from the 64
// batch means;
// t is CPU time (getrusage, all threads of the process, lavapipe's included), because the machine
// is shared. The like-for-like figures come first ("like_for_like"): FOM per CPU-second on both
// sides, against the MCML reference with CONV (the pencil response convolved with the Gaussian
// beam afterwards, as MCML's users do and as vpsim does inside its run; every tally here is of the
// Gaussian beam). The others are kept and labelled: "_per_machine" divides vpsim's CPU time by
// the threads it ran on (the machine's cores) while the single-threaded reference keeps its own,
// so it credits vpsim with the machine's cores; "_vs_mcml_direct" is against the reference
// tracing the Gaussian beam's launch offsets, whose bins are several times noisier near the axis.
// The reference is pinned to MCML 1.2.2 built here (-O3): 19 million interactions per CPU-second
// on the slurry-like case; it must land within +-40%.
// Usage: bench_photon_mc [auto|cpu|vulkan] [scale]   (run from the repository root; scale
// multiplies every photon count, default 1; auto: the shader on a hardware GPU, else the CPU
// path, as vpsim chooses; vulkan forces the shader, also on lavapipe)

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "mcml_reference.h"
#include "vpsim/core/error.h"
#include "vpsim/core/run_context.h"
#include "vpsim/gpu/context.h"
#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/optics/material.h"
#include "vpsim/transport/beam_convolution.h"
#include "vpsim/transport/photon_mc.h"

namespace {

using namespace vpsim::transport;
/// Keys in the order written, so the like-for-like figures print first.
using Json = nlohmann::ordered_json;
constexpr double MCML_INTERACTIONS_PER_CPU_SECOND = 19.0e6;  // MCML 1.2.2 -O3, measured here

double cpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    std::string a, b, c;
    in >> a >> b >> c;
    return a + " " + b + " " + c;
}

/// Batch statistics: mean and variance of the mean from MC_BATCHES batch values.
struct Stat {
    double mean = 0, variance = 0;
};
template <class Values>
Stat batchStat(const Values& v) {
    Stat s;
    for (double x : v) s.mean += x;
    s.mean /= double(v.size());
    for (double x : v) s.variance += (x - s.mean) * (x - s.mean);
    s.variance /= double(v.size()) * (v.size() - 1.0);
    return s;
}

/// The cure-front bins of a grid: z centre in [De, 3 De], r centre < We.
std::vector<size_t> cureFrontBins(const CylindricalGrid& g, double we, double de) {
    std::vector<size_t> bins;
    const double dr = g.rMax / g.rBins, dz = g.zMax / g.zBins;
    for (uint32_t iz = 0; iz < g.zBins; ++iz)
        for (uint32_t ir = 0; ir < g.rBins; ++ir) {
            double z = (iz + 0.5) * dz, r = (ir + 0.5) * dr;
            if (z >= de && z <= 3 * de && r < we) bins.push_back(size_t(iz) * g.rBins + ir);
        }
    return bins;
}

/// Mean relative variance of the bins' means, from per-batch bin values
/// (value(b, i): fraction of the batch's launched weight in bin i).
template <class Value>
double binsRelativeVariance(const std::vector<size_t>& bins, Value value) {
    double sum = 0;
    int used = 0;
    for (size_t i : bins) {
        std::array<double, MC_BATCHES> v;
        for (int b = 0; b < MC_BATCHES; ++b) v[b] = value(b, i);
        Stat s = batchStat(v);
        if (!(s.mean > 0)) continue;
        sum += s.variance / (s.mean * s.mean);
        ++used;
    }
    return used ? sum / used : INFINITY;
}

struct Figures {
    Stat rd, within30, within84;
    double binsRelVar = 0, cpu = 0, wall = 0, threads = 1, interactionsPerPhoton = 0;
    uint64_t photons = 0;
    double fom(double variance, bool perMachine) const {
        return 1.0 / (variance * (perMachine ? cpu / threads : cpu));
    }
    Json json() const {
        return {{"photons", photons},
                {"cpu_seconds", cpu},
                {"wall_seconds", wall},
                {"threads", threads},
                {"interactions_per_photon", interactionsPerPhoton},
                {"interactions_per_cpu_second", interactionsPerPhoton * photons / cpu},
                {"diffuse_reflectance", rd.mean},
                {"diffuse_reflectance_stderr", std::sqrt(rd.variance)},
                {"absorbed_within_30um", within30.mean},
                {"absorbed_within_30um_stderr", std::sqrt(within30.variance)},
                {"absorbed_within_84um", within84.mean},
                {"absorbed_within_84um_stderr", std::sqrt(within84.variance)},
                {"cure_front_bins_mean_relative_stderr", std::sqrt(binsRelVar)},
                {"fom_per_cpu_second",
                 {{"diffuse_reflectance", fom(rd.variance, false)},
                  {"absorbed_within_30um", fom(within30.variance, false)},
                  {"absorbed_within_84um", fom(within84.variance, false)},
                  {"cure_front_bins", fom(binsRelVar, false)}}},
                {"fom_per_machine",
                 {{"diffuse_reflectance", fom(rd.variance, true)},
                  {"absorbed_within_30um", fom(within30.variance, true)},
                  {"absorbed_within_84um", fom(within84.variance, true)},
                  {"cure_front_bins", fom(binsRelVar, true)}}}};
    }
};

Figures vpsimFigures(const McResult& r, const std::vector<size_t>& bins, double cpu,
                     double threads) {
    Figures f;
    // The estimates vpsim reports: for the collision and track-length estimators the tallies
    // corrected by their control variates (McResult::diffuse).
    f.rd = batchStat(r.diffuseBatches());
    f.within30 = batchStat(r.absorbedWithinBatches(0));
    f.within84 = batchStat(r.absorbedWithinBatches(1));
    const size_t perBatch = r.absorbedRZ.size();
    f.binsRelVar = binsRelativeVariance(bins, [&](int b, size_t i) {
        return double(r.absorbedRZBatches[b * perBatch + i]) /
               double(r.batches[b].photons * r.launchWeight);
    });
    f.cpu = cpu;
    f.wall = r.seconds;
    f.threads = threads;
    f.photons = r.total().photons;
    f.interactionsPerPhoton = r.interactionsPerPhoton();
    return f;
}

/// One run of the MCML reference: its tallies and CPU time.
struct McmlRun {
    bench::McmlTally tally;
    double cpu = 0;
};

/// The MCML reference on `s`; with `conv`, as MCML users get a Gaussian beam: the pencil response
/// (on vpsim's pencil grid) convolved with the beam afterwards, as MCML's CONV program does (with
/// vpsim's ring weights, the convolution's time included).
McmlRun mcmlRun(const McSetup& s, bool conv) {
    const double start = cpuSeconds();
    const McSetup traced = conv ? vpsim::transport::pencilSetup(s) : s;
    McmlRun run{bench::McmlReference(traced).run()};
    bench::McmlTally& t = run.tally;
    if (conv) {
        const auto& in = traced.bins;
        const auto& o = s.bins;
        const std::vector<double> w = vpsim::transport::ringWeights(
            o.rBins, o.rMax / o.rBins, in.rBins, in.rMax / in.rBins, s.w0);
        std::vector<double> out(size_t(o.rBins) * o.zBins * MC_BATCHES);  // [batch][z][r] rows
        vpsim::transport::convolveRings(t.absorbedRZ.data(), out.data(),
                                        size_t(o.zBins) * MC_BATCHES, in.rBins, o.rBins, w);
        t.absorbedRZ = std::move(out);
    }
    run.cpu = cpuSeconds() - start;
    return run;
}

/// The figures of a reference run of `s` (on the output grid of `s`).
Figures mcmlFigures(const McSetup& s, const McmlRun& run, const std::vector<size_t>& bins) {
    const bench::McmlTally& t = run.tally;
    Figures f;
    f.cpu = run.cpu;
    std::array<double, MC_BATCHES> rd, w30, w84;
    for (int b = 0; b < MC_BATCHES; ++b) {
        double n = double(t.photons[b]);
        rd[b] = t.diffuse[b] / n;
        w30[b] = t.within30[b] / n;
        w84[b] = t.within84[b] / n;
    }
    f.rd = batchStat(rd);
    f.within30 = batchStat(w30);
    f.within84 = batchStat(w84);
    const size_t perBatch = size_t(s.bins.rBins) * s.bins.zBins;
    f.binsRelVar = binsRelativeVariance(bins, [&](int b, size_t i) {
        return t.absorbedRZ[b * perBatch + i] / double(t.photons[b]);
    });
    f.wall = f.cpu;
    f.photons = s.photons;
    f.interactionsPerPhoton = double(t.interactions) / double(s.photons);
    return f;
}

/// FOM(a) / FOM(b) of each figure; perMachine: vpsim's CPU time over its threads (see the top).
Json ratios(const Figures& a, const Figures& b, bool perMachine) {
    auto r = [&](double va, double vb) { return a.fom(va, perMachine) / b.fom(vb, perMachine); };
    return {{"diffuse_reflectance", r(a.rd.variance, b.rd.variance)},
            {"absorbed_within_30um", r(a.within30.variance, b.within30.variance)},
            {"absorbed_within_84um", r(a.within84.variance, b.within84.variance)},
            {"cure_front_bins", r(a.binsRelVar, b.binsRelVar)}};
}

Json runCase(const std::string& caseName, const vpsim::optics::MediumOptics& optics,
             const std::shared_ptr<vpsim::gpu::Context>& context, double scale) {
    McSetup s = vpsim::kernel::kernelSetup(optics, 0.05);
    // The estimators as `vpsim mc` runs them: with the control variates the kernel's own runs
    // leave out (they change no bin).
    s.controlVariates = McSetup{}.controlVariates;
    s.depths = {0.030, 0.084};
    s.binsPerBatch = true;
    s.seed = 11;
    const double threads =
        context ? double(std::thread::hardware_concurrency()) : std::thread::hardware_concurrency();
    auto runOne = [&](Estimator e, uint64_t photons, McResult& out) {
        McSetup run = s;
        run.estimator = e;
        run.photons = std::max<uint64_t>(64, uint64_t(photons * scale));
        double start = cpuSeconds();
        out = runPhotonMc(run, context);
        return cpuSeconds() - start;
    };
    // Every estimator (the analog-transport ones at more photons: they are cheaper per photon)
    // and the MCML reference. This machine's speed drifts by tens of percent over a minute, so the
    // runs the headline ratios compare go back to back: the default estimator, the analog one,
    // then the reference (plain and with CONV), then the other estimators.
    // The cure front comes from a kernel fitted to the default estimator's run.
    const Estimator fallback = McSetup{}.estimator;
    std::map<std::string, Figures> f;
    std::map<std::string, McResult> runs;
    std::map<std::string, double> cpu;
    auto runEstimator = [&](Estimator e) {
        const std::string name = estimatorName(e);
        if (runs.count(name)) return;
        const bool implicitCapture = e == Estimator::Implicit || e == Estimator::ImplicitTrack;
        cpu[name] = runOne(e, implicitCapture ? 400000 : 3000000, runs[name]);
    };
    runEstimator(fallback);
    runEstimator(Estimator::Analog);
    McSetup reference = s;
    reference.photons = std::max<uint64_t>(64, uint64_t(150000 * scale));
    const McmlRun mcml = mcmlRun(reference, false), mcmlConv = mcmlRun(reference, true);
    for (Estimator e :
         {Estimator::Collision, Estimator::Track, Estimator::ImplicitTrack, Estimator::Implicit})
        runEstimator(e);
    const std::string defaultName = estimatorName(fallback);
    vpsim::kernel::BeamKernel k = vpsim::kernel::kernelFromMonteCarlo(runs[defaultName], 10.0);
    std::vector<size_t> bins = cureFrontBins(s.bins, k.fit.we3d, k.fit.de3d);
    for (const auto& [name, run] : runs) f[name] = vpsimFigures(run, bins, cpu[name], threads);
    const Figures& fDefault = f[defaultName];
    const Figures& fAnalog = f["analog"];
    Figures fMcml = mcmlFigures(reference, mcml, bins);
    Figures fMcmlConv = mcmlFigures(reference, mcmlConv, bins);

    Json j;
    j["case"] = caseName;
    // Like for like first: per CPU-second, against MCML with CONV (what vpsim does for the beam).
    j["fom_ratio_vs_mcml_conv_per_cpu_second"] = ratios(fDefault, fMcmlConv, false);
    j["fom_ratio_vs_analog"] = ratios(fDefault, fAnalog, false);  // same threads on both sides
    j["mua_per_mm"] = optics.mua;
    j["mus_per_mm"] = optics.mus;
    j["g"] = optics.g;
    j["backend"] = runs[defaultName].backend;
    j["We3D_um"] = k.fit.we3d * 1e3;
    j["De3D_um"] = k.fit.de3d * 1e3;
    j["cure_front_bin_count"] = bins.size();
    j["default_estimator"] = defaultName;
    for (const auto& [name, figures] : f) {
        j["estimators"][name] = figures.json();
        if (name != "analog")
            j["fom_ratio_vs_analog_by_estimator"][name] = ratios(figures, fAnalog, false);
        j["fom_ratio_vs_mcml_conv_per_cpu_second_by_estimator"][name] =
            ratios(figures, fMcmlConv, false);
    }
    j["mcml_reference_with_conv"] = fMcmlConv.json();
    j["mcml_reference_direct"] = fMcml.json();
    j["mcml_reference_interactions_per_cpu_second"] =
        fMcml.interactionsPerPhoton * fMcml.photons / fMcml.cpu;
    // The others, labelled: against the reference tracing the Gaussian beam directly, and with
    // vpsim's CPU time divided by its threads (the machine's cores).
    j["fom_ratio_vs_mcml_direct_per_cpu_second"] = ratios(fDefault, fMcml, false);
    j["fom_ratio_vs_mcml_conv_per_machine"] = ratios(fDefault, fMcmlConv, true);
    j["fom_ratio_vs_mcml_direct_per_machine"] = ratios(fDefault, fMcml, true);
    // Same physics: each estimator's figures against the analog ones, in combined sigmas.
    auto sigmas = [](const Stat& a, const Stat& b) {
        return std::abs(a.mean - b.mean) / std::sqrt(a.variance + b.variance);
    };
    j["agreement_sigmas_default_vs_analog"] = {
        {"diffuse_reflectance", sigmas(fDefault.rd, fAnalog.rd)},
        {"absorbed_within_30um", sigmas(fDefault.within30, fAnalog.within30)},
        {"absorbed_within_84um", sigmas(fDefault.within84, fAnalog.within84)}};
    j["agreement_sigmas_mcml_vs_analog"] = {
        {"diffuse_reflectance", sigmas(fMcml.rd, fAnalog.rd)},
        {"absorbed_within_30um", sigmas(fMcml.within30, fAnalog.within30)},
        {"absorbed_within_84um", sigmas(fMcml.within84, fAnalog.within84)}};
    return j;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string backend = argc > 1 ? argv[1] : "auto";
    const double scale = argc > 2 ? std::atof(argv[2]) : 1.0;
    Json out{{"benchmark", "photon_mc_efficiency"}};
    // The headline (like-for-like) figures are filled in once measured, but print first.
    out["like_for_like"] = Json::object();
    out["cpu_cores"] = std::thread::hardware_concurrency();
    out["load_average_start"] = loadAverage();
    try {
        std::shared_ptr<vpsim::gpu::Context> context;
        if (backend != "cpu") {
            try {
                context = vpsim::gpu::Context::create();
            } catch (const vpsim::Error& e) {
                if (backend == "vulkan") throw;
                out["gpu_error"] = e.what();
            }
        }
        // As vpsim runs (gpu::monteCarloContext): shaders on hardware GPUs; on a CPU driver the TBB
        // path (for the default estimator as fast per CPU-second as lavapipe, with no pipeline
        // compile), unless the shader is forced with "vulkan".
        vpsim::RunContext run;
        run.gpu = context;
        run.monteCarloOnCpuDevices = backend == "vulkan";
        std::shared_ptr<vpsim::gpu::Context> shader = vpsim::gpu::monteCarloContext(run);
        if (context && !shader) out["shader_device_skipped"] = context->info().name;
        context = std::move(shader);
        vpsim::optics::MediumOptics hg;
        hg.mua = 8.4;
        hg.mus = 303.0;
        hg.g = 0.9;
        hg.refractiveIndex = 1.0;
        Json slurryHg = runCase("slurry-like HG", hg, context, scale);
        Json seed000 =
            runCase("seed-000 Mie slurry",
                    vpsim::optics::loadMediumOptics("examples/materials/alumina-seed000.json"),
                    context, scale);
        // The headline figures: the slurry-like case (the one MCML was measured on).
        out["like_for_like"] = {
            {"basis",
             "slurry-like HG case; figure of merit 1/(sigma^2 t) per CPU-second on both sides "
             "(vpsim's CPU time on all its threads, the reference's on one); MCML reference "
             "with CONV (pencil response convolved with the Gaussian beam, as vpsim does)"},
            {"fom_ratio_vs_mcml_conv_per_cpu_second",
             slurryHg["fom_ratio_vs_mcml_conv_per_cpu_second"]},
            {"fom_ratio_vs_analog", slurryHg["fom_ratio_vs_analog"]},
            {"seed000_fom_ratio_vs_mcml_conv_per_cpu_second",
             seed000["fom_ratio_vs_mcml_conv_per_cpu_second"]}};
        out["cases"] = {slurryHg, seed000};
        // Kept, labelled: not like for like (see the top of this file).
        for (const char* key :
             {"fom_ratio_vs_mcml_direct_per_cpu_second", "fom_ratio_vs_mcml_conv_per_machine",
              "fom_ratio_vs_mcml_direct_per_machine", "mcml_reference_interactions_per_cpu_second"})
            out[key] = slurryHg[key];
        const double rate = slurryHg["mcml_reference_interactions_per_cpu_second"];
        out["mcml_1_2_2_interactions_per_cpu_second"] = MCML_INTERACTIONS_PER_CPU_SECOND;
        out["mcml_reference_over_mcml_1_2_2"] = rate / MCML_INTERACTIONS_PER_CPU_SECOND;
        bool ok3 = true, ok08 = true, ok10 = true, ok10conv = true, band = true;
        for (const auto& c : out["cases"]) {
            const auto& va = c["fom_ratio_vs_analog"];
            ok3 = ok3 && va["cure_front_bins"].get<double>() >= 3.0;
            for (const auto& [k, v] : va.items()) ok08 = ok08 && v.get<double>() >= 0.8;
            const auto& vm = c["fom_ratio_vs_mcml_direct_per_machine"];
            ok10 = ok10 && vm["diffuse_reflectance"].get<double>() >= 10.0 &&
                   vm["cure_front_bins"].get<double>() >= 10.0;
            const auto& vc = c["fom_ratio_vs_mcml_conv_per_machine"];
            ok10conv = ok10conv && vc["diffuse_reflectance"].get<double>() >= 10.0 &&
                       vc["cure_front_bins"].get<double>() >= 10.0;
        }
        band = std::abs(rate / MCML_INTERACTIONS_PER_CPU_SECOND - 1.0) <= 0.4;
        // Issue 14's targets as they were set (per machine); quote the like-for-like figures.
        out["targets"] = {
            {"default_vs_analog_cure_front_bins_at_least_3x", ok3},
            {"default_vs_analog_every_figure_at_least_0.8x", ok08},
            {"default_vs_mcml_direct_per_machine_rd_and_cure_front_at_least_10x", ok10},
            {"default_vs_mcml_conv_per_machine_rd_and_cure_front_at_least_10x", ok10conv},
            {"mcml_reference_within_40_percent_of_mcml_1_2_2", band}};
    } catch (const vpsim::Error& e) {
        out["error"] = e.what();
        std::cout << out.dump(2) << std::endl;
        return 1;
    }
    out["load_average_end"] = loadAverage();
    std::cout << out.dump(2) << std::endl;
    return 0;
}
