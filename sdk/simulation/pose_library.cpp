#include "simulation/pose_library.hpp"

#include <Eigen/Geometry>

#include <cmath>

namespace ssc::simulation {

namespace {

using A = anatomy::JointAngles;

// Reminders of the conventions (anatomy/named_poses.hpp): the rest pose holds the upper arms 43°
// out from the body, the elbows 42° and the knees 7° bent; upperarm -x' forward, -z' up sideways,
// +z' down towards the body; lowerarm +40 straight, -x' bends; thigh -x' forward, -z' out
// sideways; calf +x' bends the knee; foot +x' points the toes down; spine and neck +x' forward, y'
// turns, z' leans; the pelvis (no limits) turns everything above and below it.
const A kArmsStraight{"lowerarm", 40, 0, 0};
const A kArmsDown{"upperarm", 0, 0, 35};
// Arms crossed over the chest: the upper arms forward enough that the forearms clear a heavy chest.
const A kArmsCrossed{"upperarm", -70, 25, 10};
const A kForearmsCrossed{"lowerarm", -95, 0, 0};

std::vector<LibraryPose> make_library() {
    std::vector<LibraryPose> l;
    auto named = [&](const char* name, const char* description) { l.push_back({name, description, name, {}}); };
    auto pose = [&](const char* name, const char* description, std::vector<A> angles) { l.push_back({name, description, "", std::move(angles)}); };
    // The named poses.
    named("a_pose", "standing, arms about 45 degrees out");
    named("t_pose", "standing, arms out horizontal");
    named("arms_raised", "standing, arms straight up beside the head");
    named("sitting", "sitting on a chair");
    named("crouching", "crouching, heels down, arms forward");
    named("kneeling", "kneeling upright on both knees");
    named("bending_forward", "bending forward from the hips, arms hanging");
    named("bent_over_arms_raised", "bent over, arms raised forward past the head");
    named("lunge", "lunge, left leg forward");
    named("arms_behind_back", "hands behind the back");
    // Standing, the arms.
    pose("arms_down", "standing, arms at the sides", {kArmsDown, {"lowerarm", 30, 0, 0}});
    pose("arms_forward", "arms straight forward, horizontal", {{"upperarm", -90, 0, 15}, kArmsStraight});
    pose("arms_forward_up", "arms reaching forward and up", {{"upperarm", -150, 0, 5}, kArmsStraight});
    pose("hands_on_belly", "hands together on the belly, elbows out", {{"upperarm", 10, 60, 5}, {"lowerarm", -75, 0, 0}});
    pose("hands_behind_head", "hands behind the head, elbows out", {{"upperarm", -15, -60, -95}, {"lowerarm", -105, 0, 0}});
    pose("arms_crossed", "arms crossed over the chest, hands at the shoulders", {kArmsCrossed, kForearmsCrossed});
    // No turn of the upper arm: turned in 60 degrees, the bent forearms went through a heavy chest.
    pose("forearms_forward", "upper arms at the sides, forearms forward", {{"upperarm", 0, 0, 35}, {"lowerarm", -90, 0, 0}});
    pose("reach_up_right", "the right arm reaching straight up, the trunk leaning left",
         {{"upperarm", 0, 0, -135, 'r'}, {"lowerarm", 40, 0, 0, 'r'}, {"spine_02", 0, 0, 10, 'm'}, {"spine_03", 0, 0, 10, 'm'}});
    pose("reach_sideways_left", "the left arm reaching out sideways, the trunk leaning with it",
         {{"upperarm", 0, 0, -50, 'l'}, {"lowerarm", 40, 0, 0, 'l'}, {"spine_02", 0, 0, -12, 'm'}, {"spine_03", 0, 0, -12, 'm'}});
    pose("one_arm_up", "the left arm up, the right down at the side",
         {{"upperarm", 0, 0, -130, 'l'}, {"lowerarm", 40, 0, 0, 'l'}, {"upperarm", 0, 0, 35, 'r'}});
    pose("arm_across_chest", "the left arm drawn across the chest by the right hand",
         {{"upperarm", -95, 70, 20, 'l'}, {"lowerarm", 35, 0, 0, 'l'}, {"upperarm", -55, 40, 20, 'r'}, {"lowerarm", -90, 0, 0, 'r'}});
    pose("boxing_guard", "fists up in front of the face, knees soft",
         {{"upperarm", -55, 30, 30}, {"lowerarm", -100, 0, 0}, {"thigh", -20, 0, 0}, {"calf", 25, 0, 0}});
    // Standing, the trunk and head.
    pose("trunk_twist", "the trunk turned to the left, arms out",
         {{"spine_01", 0, 15, 0, 'm'}, {"spine_02", 0, 15, 0, 'm'}, {"spine_03", 0, 15, 0, 'm'}, {"neck_01", 0, 20, 0, 'm'},
          {"upperarm", 0, 0, -40}, kArmsStraight});
    pose("side_bend", "the trunk bent to the right, the left arm over the head",
         {{"spine_01", 0, 0, 13, 'm'}, {"spine_02", 0, 0, 13, 'm'}, {"spine_03", 0, 0, 13, 'm'}, {"upperarm", 0, 0, -120, 'l'},
          {"lowerarm", 20, 0, 0, 'l'}});
    pose("looking_up", "head tipped back, looking up", {{"neck_01", -25, 0, 0, 'm'}, {"head", -22, 0, 0, 'm'}});
    pose("head_turned", "head turned to the right, tilted", {{"neck_01", 0, -30, 10, 'm'}, {"head", 0, -25, 0, 'm'}});
    pose("touching_toes", "bending down to the toes, legs straight",
         {{"pelvis", 80, 0, 0, 'm'}, {"thigh", -80, 0, 0}, {"spine_01", 28, 0, 0, 'm'}, {"spine_02", 28, 0, 0, 'm'}, {"spine_03", 25, 0, 0, 'm'},
          {"upperarm", -95, -20, -15}, kArmsStraight});
    pose("hands_on_knees", "leaning forward with the hands on the bent knees",
         {{"pelvis", 45, 0, 0, 'm'}, {"thigh", -80, 0, 0}, {"calf", 60, 0, 0}, {"foot", -15, 0, 0}, {"spine_01", 15, 0, 0, 'm'},
          {"upperarm", -60, 0, 35}, {"lowerarm", 35, 0, 0}});
    // Standing, the legs.
    pose("one_leg_stand", "standing on the right leg, the left knee raised", {{"thigh", -70, 0, 0, 'l'}, {"calf", 90, 0, 0, 'l'}, {"foot", 20, 0, 0, 'l'}});
    pose("quad_stretch", "standing on the left leg, the right heel held at the buttock",
         {{"thigh", 15, 0, 0, 'r'}, {"calf", 130, 0, 0, 'r'}, {"foot", 40, 0, 0, 'r'}, {"upperarm", 40, 0, 30, 'r'}, {"lowerarm", -40, 0, 0, 'r'}});
    pose("leg_out_sideways", "the left leg raised out sideways, arms out",
         {{"thigh", 0, 0, -45, 'l'}, {"thigh", 0, 0, -5, 'r'}, {"upperarm", 0, 0, -40}, kArmsStraight});
    pose("front_kick", "the left leg kicked forward and up, knee straight",
         {{"thigh", -95, 0, 0, 'l'}, {"calf", 0, 0, 0, 'l'}, {"upperarm", -30, 0, 10}});
    pose("walking_step", "mid-stride walking, arms swinging",
         {{"thigh", -25, 0, 0, 'l'}, {"calf", 10, 0, 0, 'l'}, {"thigh", 15, 0, 0, 'r'}, {"calf", 20, 0, 0, 'r'}, {"foot", 15, 0, 0, 'r'},
          {"upperarm", 25, 0, 35, 'l'}, {"upperarm", -25, 0, 35, 'r'}, {"lowerarm", 20, 0, 0}});
    pose("running_step", "running, the left knee driven forward",
         {{"thigh", -60, 0, 0, 'l'}, {"calf", 90, 0, 0, 'l'}, {"thigh", 25, 0, 0, 'r'}, {"calf", 70, 0, 0, 'r'}, {"foot", 30, 0, 0, 'r'},
          {"spine_01", 10, 0, 0, 'm'}, {"upperarm", 45, 0, 35, 'l'}, {"upperarm", -50, 0, 35, 'r'}, {"lowerarm", -50, 0, 0}});
    pose("wide_stance", "feet wide apart, knees bent (horse stance)",
         {{"thigh", -45, 0, -35}, {"calf", 60, 0, 0}, {"foot", -10, 0, 0}, {"upperarm", -20, 0, 30}});
    // Squatting and kneeling.
    pose("deep_squat", "a deep squat, heels down, arms forward",
         {{"pelvis", 25, 0, 0, 'm'}, {"thigh", -120, 0, -20}, {"calf", 130, 0, 0}, {"foot", -22, 0, 0}, {"spine_01", 15, 0, 0, 'm'},
          {"upperarm", -85, 0, 35}, {"lowerarm", 30, 0, 0}});
    pose("squat_arms_raised", "a squat with the arms straight overhead",
         {{"pelvis", 20, 0, 0, 'm'}, {"thigh", -110, 0, -20}, {"calf", 120, 0, 0}, {"foot", -20, 0, 0}, {"upperarm", -165, -40, 15}, kArmsStraight});
    pose("kneeling_one_knee", "kneeling on the right knee, the left foot forward",
         {{"thigh", -90, 0, 0, 'l'}, {"calf", 90, 0, 0, 'l'}, {"thigh", 0, 0, 0, 'r'}, {"calf", 90, 0, 0, 'r'}, {"foot", 40, 0, 0, 'r'},
          {"upperarm", -10, 0, 30}});
    pose("kneeling_sitting_back", "kneeling, sitting back on the heels, hands on the thighs",
         {{"pelvis", 10, 0, 0, 'm'}, {"thigh", -60, 0, 0}, {"calf", 120, 0, 0}, {"foot", 45, 0, 0}, {"upperarm", -40, 0, 30}, {"lowerarm", 20, 0, 0}});
    pose("crawling", "on hands and knees",
         {{"pelvis", 90, 0, 0, 'm'}, {"thigh", -90, 0, 0}, {"calf", 90, 0, 0}, {"foot", 40, 0, 0}, {"neck_01", -25, 0, 0, 'm'},
          {"upperarm", -90, 0, 10}, kArmsStraight});
    // Sitting.
    pose("sitting_leaning_back", "sitting, leaning back, arms crossed",
         {{"pelvis", -20, 0, 0, 'm'}, {"thigh", -70, 0, 0}, {"calf", 83, 0, 0}, kArmsCrossed, kForearmsCrossed});
    pose("sitting_legs_crossed", "sitting on a chair, the left knee over the right",
         {{"thigh", -95, 0, 10, 'l'}, {"calf", 80, 0, 0, 'l'}, {"thigh", -90, 0, 0, 'r'}, {"calf", 83, 0, 0, 'r'}, {"upperarm", -15, 0, 33},
          {"lowerarm", -5, 0, 0}});
    pose("sitting_floor_legs_out", "sitting on the floor, legs straight out, hands on the floor behind",
         {{"thigh", -90, 0, 0}, {"calf", -5, 0, 0}, {"upperarm", 40, 0, 25}, kArmsStraight});
    pose("sitting_floor_knees_wide", "sitting on the floor, knees wide apart, feet in front",
         {{"thigh", -80, 40, -40}, {"calf", 125, 0, 0}, {"upperarm", -20, 0, 30}, {"lowerarm", -20, 0, 0}});
    // Lying: a standing pose turned as a whole (LibraryPose::lying).
    auto lying = [&](const char* name, const char* description, std::vector<A> angles, double pitch, double roll) {
        l.push_back({name, description, "", std::move(angles), pitch, roll});
    };
    lying("lying_on_back", "lying on the back, arms at the sides", {kArmsDown}, -90, 0);
    lying("lying_on_back_knees_up", "lying on the back, knees raised", {{"thigh", -60, 0, 0}, {"calf", 100, 0, 0}, {"upperarm", 0, 0, 25}}, -90, 0);
    lying("lying_on_side", "lying on the right side, knees and arms a little bent",
          {{"thigh", -40, 0, 0}, {"calf", 50, 0, 0}, {"upperarm", -60, 0, 20}, {"lowerarm", -20, 0, 0}}, 0, 90);
    lying("lying_on_front", "lying on the front, arms beside the head", {{"foot", 40, 0, 0}, {"upperarm", 0, 0, -90}, {"lowerarm", -60, 0, 0}}, 90, 0);
    return l;
}

}  // namespace

const std::vector<LibraryPose>& pose_library() {
    static const std::vector<LibraryPose> library = make_library();
    return library;
}

Eigen::Matrix3d library_orientation(const LibraryPose& pose) {
    constexpr double deg = M_PI / 180;
    return (Eigen::AngleAxisd(deg * pose.pitch, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(deg * pose.roll, Eigen::Vector3d::UnitZ())).toRotationMatrix();
}

std::vector<float> library_pose(const Model& model, const LibraryPose& pose) {
    return pose.named.empty() ? anatomy::pose_from_angles(model, pose.angles) : anatomy::named_pose(model, pose.named);
}

}  // namespace ssc::simulation
