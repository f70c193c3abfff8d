#include "population.hpp"

#include "common/error.hpp"
#include "common/files.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

namespace ssc::training {

double stature(const std::vector<float>& xyz) {
    float lo = 1e30f, hi = -1e30f;
    for (uint32_t v = 0; v < mh::kBodyVertices; ++v) {
        lo = std::min(lo, xyz[3 * v + 1]);
        hi = std::max(hi, xyz[3 * v + 1]);
    }
    return double(hi) - lo;
}

double body_volume(const mh::Assets& a, const std::vector<float>& xyz) {
    double six_v = 0;
    const auto& q = a.base.body_quads;
    auto tet = [&](uint32_t i, uint32_t j, uint32_t k) {
        const float *A = &xyz[3 * i], *B = &xyz[3 * j], *C = &xyz[3 * k];
        six_v += double(A[0]) * (double(B[1]) * C[2] - double(B[2]) * C[1]) - double(A[1]) * (double(B[0]) * C[2] - double(B[2]) * C[0]) +
                 double(A[2]) * (double(B[0]) * C[1] - double(B[1]) * C[0]);
    };
    for (std::size_t f = 0; f + 4 <= q.size(); f += 4) {
        tet(q[f], q[f + 1], q[f + 2]);
        tet(q[f], q[f + 2], q[f + 3]);
    }
    return std::abs(six_v) / 6.0;
}

namespace {

double clamp01(double x) { return std::min(1.0, std::max(0.0, x)); }

// Sets one macro slider so that measure(body) reaches target, by bisection (the measure grows with
// the slider). Height and weight tokens weight their targets by max(0, 2x - 1) and max(0, 1 - 2x),
// so the body is linear in the slider on each side of 0.5: three generated bodies give every value.
// Only the body vertices are blended (the measures read nothing else).
template <class Measure>
void calibrate(const mh::Assets& a, BodyParams& b, double mh::MacroSliders::*slider, int iterations, double target,
               Measure&& measure, std::vector<float>& xyz) {
    std::vector<float> mid, up_body, down_body;
    b.macro.*slider = 0.5;
    mh::generate_body(a, b.macro, b.modifiers, mid);
    b.macro.*slider = 1.0;
    mh::generate_body(a, b.macro, b.modifiers, up_body);
    b.macro.*slider = 0.0;
    mh::generate_body(a, b.macro, b.modifiers, down_body);
    const std::size_t n = 3ull * mh::kBodyVertices;
    xyz.resize(n);
    double lo = 0, hi = 1;
    for (int it = 0; it < iterations; ++it) {
        const double x = 0.5 * (lo + hi);
        const float up = float(std::max(0.0, 2 * x - 1)), down = float(std::max(0.0, 1 - 2 * x));
        for (std::size_t i = 0; i < n; ++i) xyz[i] = mid[i] + up * (up_body[i] - mid[i]) + down * (down_body[i] - mid[i]);
        (measure(xyz) < target ? lo : hi) = x;
    }
    b.macro.*slider = 0.5 * (lo + hi);
}

// Height slider -> target stature.
void calibrate_height(const mh::Assets& a, BodyParams& b, std::vector<float>& xyz) {
    calibrate(a, b, &mh::MacroSliders::height, 24, b.target_stature, [](const std::vector<float>& v) { return stature(v); }, xyz);
}

// Weight slider -> target BMI (mass from volume x density over stature squared).
void calibrate_weight(const mh::Assets& a, BodyParams& b, std::vector<float>& xyz) {
    calibrate(a, b, &mh::MacroSliders::weight, 20, b.target_bmi, [&](const std::vector<float>& v) {
        const double h = stature(v);
        return body_volume(a, v) * kBodyDensity / (h * h);
    }, xyz);
}

}  // namespace

std::vector<BodyParams> sample_population(const mh::Assets& a, const PopulationSpec& spec, const StatureStats& stats,
                                          const SamplingProgress& progress) {
    std::mt19937_64 rng(spec.seed);
    std::normal_distribution<double> N01;
    std::uniform_real_distribution<double> U01;
    std::gamma_distribution<double> gamma(0.7, 1.0);
    std::vector<BodyParams> out(spec.count);
    std::vector<float> xyz;
    for (auto& b : out) {
        const uint32_t done = uint32_t(&b - out.data());
        if (progress && !progress(done, spec.count)) fail(SSC_ERROR_CANCELLED, "population sampling cancelled");
        b.male = U01(rng) < 0.5;
        b.age_years = spec.min_age + (spec.max_age - spec.min_age) * U01(rng);
        auto& m = b.macro;
        m.gender = b.male ? clamp01(1 - std::abs(0.05 * N01(rng))) : clamp01(std::abs(0.05 * N01(rng)));
        m.age = mh::age_slider(b.age_years);
        // Ethnic mix: a Dirichlet(0.7, 0.7, 0.7) draw, mostly one dominant group.
        const double e1 = gamma(rng), e2 = gamma(rng), e3 = gamma(rng);
        m.african = e1 / (e1 + e2 + e3);
        m.asian = e2 / (e1 + e2 + e3);
        m.caucasian = e3 / (e1 + e2 + e3);
        // Weight is calibrated to a BMI below; muscle declines with age.
        const double decades = (b.age_years - 40) / 10;
        m.weight = 0.5;
        m.muscle = clamp01(0.5 - 0.02 * decades + 0.14 * N01(rng));
        m.proportions = clamp01(0.5 + 0.15 * N01(rng));
        m.breast_size = clamp01(0.5 + 0.15 * N01(rng));
        m.breast_firmness = clamp01(0.5 - 0.03 * decades + 0.15 * N01(rng));
        b.modifiers.assign(a.modifiers.size(), 0.0);
        // Body-shape modifiers: small two-sided variations everywhere; one body-shape type,
        // of the body's sex, for half of the bodies.
        std::vector<std::size_t> shapes;
        for (std::size_t i = 0; i < a.modifiers.size(); ++i) {
            const auto& mod = a.modifiers[i];
            if (mod.decr >= 0) b.modifiers[i] = std::max(-1.0, std::min(1.0, spec.modifier_sd * N01(rng)));
            else if (mod.name.find(b.male ? "-man-" : "-fem-") != std::string::npos) shapes.push_back(i);
        }
        if (!shapes.empty() && U01(rng) < 0.5) b.modifiers[shapes[std::size_t(U01(rng) * shapes.size()) % shapes.size()]] = 0.5 * U01(rng);
        // Stature: survey mean and spread for the sex, minus about 1 cm per decade after 50.
        const double mean = b.male ? stats.male_mean : stats.female_mean, sd = b.male ? stats.male_sd : stats.female_sd;
        b.target_stature = mean + sd * std::max(-3.0, std::min(3.0, N01(rng))) - 0.01 * std::max(0.0, (b.age_years - 50) / 10);
        // BMI: log-normal with the survey mean and spread for the sex (BMI is right-skewed).
        const double bm = b.male ? stats.male_bmi_mean : stats.female_bmi_mean, bs = b.male ? stats.male_bmi_sd : stats.female_bmi_sd;
        const double s2 = std::log(1 + bs * bs / (bm * bm));
        b.target_bmi = std::exp(std::log(bm) - 0.5 * s2 + std::sqrt(s2) * std::max(-3.0, std::min(3.0, N01(rng))));
    }
    // Stature first, then weight at that stature, then stature again (weight moves it a little).
    for (auto& b : out) {
        calibrate_height(a, b, xyz);
        calibrate_weight(a, b, xyz);
        calibrate_height(a, b, xyz);
    }
    return out;
}

void write_population_csv(const std::string& path, const mh::Assets& a, const std::vector<BodyParams>& bodies) {
    std::ostringstream s;
    s.precision(9);
    s << "sex,age_years,target_stature_m,target_bmi,gender,age,muscle,weight,height,proportions,african,asian,caucasian,breast_size,breast_firmness";
    for (const auto& m : a.modifiers) s << "," << m.name;
    s << "\n";
    for (const auto& b : bodies) {
        const auto& m = b.macro;
        s << (b.male ? "male" : "female") << "," << b.age_years << "," << b.target_stature << "," << b.target_bmi << "," << m.gender << "," << m.age << ","
          << m.muscle << "," << m.weight << "," << m.height << "," << m.proportions << "," << m.african << "," << m.asian << ","
          << m.caucasian << "," << m.breast_size << "," << m.breast_firmness;
        for (double v : b.modifiers) s << "," << v;
        s << "\n";
    }
    const std::string text = s.str();
    write_file_atomically(path, text.data(), text.size());
}

std::vector<float> beyond_model_body(const mh::Assets& a, const BodyParams& person, std::size_t trained, std::mt19937& rng) {
    BodyParams body = person;
    std::uniform_real_distribution<double> extra(-0.5, 0.5);
    body.modifiers.resize(a.modifiers.size(), 0.0);
    for (std::size_t k = trained; k < body.modifiers.size(); ++k)
        if (a.modifiers[k].name.find("-trans") == std::string::npos) body.modifiers[k] = a.modifiers[k].decr >= 0 ? extra(rng) : 0.5 + extra(rng);
    std::vector<float> xyz;
    mh::generate_body(a, body.macro, body.modifiers, xyz);
    return xyz;
}

}  // namespace ssc::training
