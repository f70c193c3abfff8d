// Named poses (anatomy/named_poses.hpp) through the C API.
#include "anatomy/named_poses.hpp"
#include "guard.hpp"
#include "handles.hpp"

#include <algorithm>
#include <string>

using namespace ssc;
using namespace ssc::capi;

extern "C" {

uint32_t ssc_named_pose_count(void) { return uint32_t(anatomy::named_poses().size()); }

ssc_status ssc_named_pose_get_info(uint32_t index, const char** out_name, const char** out_description) {
    return guarded(__func__, [&] {
        const auto& poses = anatomy::named_poses();
        SSC_REQUIRE_ARG(index < poses.size(), "named pose " + std::to_string(index) + " is out of range (count " +
                                                  std::to_string(poses.size()) + ")");
        if (out_name) *out_name = poses[index].name;
        if (out_description) *out_description = poses[index].description;
    });
}

ssc_status ssc_model_get_named_pose(const ssc_model* model, const char* name, float* rotations, uint32_t joint_capacity) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(name, "name");
        check_output(rotations, joint_capacity, model->model.joint_count(), 0, 16);
        const auto q = anatomy::named_pose(model->model, name);
        std::copy(q.begin(), q.end(), rotations);
    });
}

}  // extern "C"
