#include "rotation.hpp"

#include <cmath>

namespace ssc {

namespace {

// Whether joint j's rotation r can be used; if not, why, in error.
bool usable(ssc_rotation_format format, const float* r, uint32_t j, std::string& error) {
    const int width = format == SSC_ROTATION_QUATERNION ? 4 : 3;
    for (int i = 0; i < width; ++i)
        if (!std::isfinite(r[i])) {
            error = "rotation of joint " + std::to_string(j) + " is not finite";
            return false;
        }
    if (format == SSC_ROTATION_QUATERNION) {
        const double n = std::sqrt(double(r[0]) * r[0] + double(r[1]) * r[1] + double(r[2]) * r[2] + double(r[3]) * r[3]);
        if (!(n > 1e-12) || !std::isfinite(n)) {
            error = "quaternion of joint " + std::to_string(j) + " has zero length";
            return false;
        }
    }
    return true;
}

}  // namespace

bool check_rotations(ssc_rotation_format format, const float* in, uint32_t count, std::string& error) {
    const int width = format == SSC_ROTATION_QUATERNION ? 4 : 3;
    for (uint32_t j = 0; j < count; ++j)
        if (!usable(format, in + std::size_t(width) * j, j, error)) return false;
    return true;
}

bool to_unit_quaternions(ssc_rotation_format format, const float* in, uint32_t count, float* out, std::string& error) {
    const int width = format == SSC_ROTATION_QUATERNION ? 4 : 3;
    for (uint32_t j = 0; j < count; ++j) {
        const float* r = in + std::size_t(width) * j;
        if (!usable(format, r, j, error)) return false;
        double q[4];
        if (format == SSC_ROTATION_QUATERNION) {
            const double n = std::sqrt(double(r[0]) * r[0] + double(r[1]) * r[1] + double(r[2]) * r[2] + double(r[3]) * r[3]);
            for (int i = 0; i < 4; ++i) q[i] = r[i] / n;
        } else {
            const double angle = std::sqrt(double(r[0]) * r[0] + double(r[1]) * r[1] + double(r[2]) * r[2]);
            // Both of the half angle, unconditionally: the compiler makes them one sincos call
            // (glibc's gives the same bits as sin and cos; the pose-only synthesis's libm time
            // about halves).
            const double half_sin = std::sin(0.5 * angle), half_cos = std::cos(0.5 * angle);
            const double s = angle > 1e-12 ? half_sin / angle : 0.5;  // sin(a/2)/a -> 1/2
            q[0] = r[0] * s;
            q[1] = r[1] * s;
            q[2] = r[2] * s;
            q[3] = half_cos;
        }
        for (int i = 0; i < 4; ++i) out[4 * j + i] = static_cast<float>(q[i]);
    }
    return true;
}

}  // namespace ssc
