#include "image/camera.h"

#include <gtest/gtest.h>

#include <cmath>

#include "verify/scenes.h"

namespace daisy {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3d directionOf(const Ray& ray) {
    return {ray.direction[0], ray.direction[1], ray.direction[2]};
}

Camera testCamera() {
    Camera camera;
    camera.name = "test";
    camera.position = {1, 2, 3};
    camera.forward = {0, 0, -1};
    camera.up = {0, 1, 0};
    camera.yFovRad = 60 * kPi / 180;
    return camera;
}

TEST(ImageCamera, CentrePixelLooksAlongForward) {
    const Camera camera = testCamera();
    // The centre of an even-sized image is the corner shared by its four middle pixels.
    const Ray ray = primaryRay(camera, 64, 48, 32, 24);
    EXPECT_FLOAT_EQ(ray.origin[0], 1);
    EXPECT_FLOAT_EQ(ray.origin[1], 2);
    EXPECT_FLOAT_EQ(ray.origin[2], 3);
    EXPECT_NEAR(ray.direction[0], 0, 1e-7);
    EXPECT_NEAR(ray.direction[1], 0, 1e-7);
    EXPECT_NEAR(ray.direction[2], -1, 1e-7);
}

// Pinhole geometry: the image's top edge is yFov/2 above the axis, its right edge
// atan(aspect tan(yFov/2)) to the right (aspect = width / height).
TEST(ImageCamera, CornerAnglesFollowTheFieldOfView) {
    const Camera camera = testCamera();
    const int width = 64, height = 48;
    const double aspect = double(width) / height;
    const double halfY = 0.5 * camera.yFovRad;
    const double halfX = std::atan(aspect * std::tan(halfY));
    const Vec3d topLeft = directionOf(primaryRay(camera, width, height, 0, 0));
    EXPECT_NEAR(length(topLeft), 1, 1e-6);
    EXPECT_NEAR(std::atan2(topLeft.y, -topLeft.z), halfY, 1e-6);  // up is +y
    EXPECT_NEAR(std::atan2(-topLeft.x, -topLeft.z), halfX, 1e-6);  // left is -x
    const Vec3d bottomRight = directionOf(primaryRay(camera, width, height, width, height));
    EXPECT_NEAR(std::atan2(-bottomRight.y, -bottomRight.z), halfY, 1e-6);
    EXPECT_NEAR(std::atan2(bottomRight.x, -bottomRight.z), halfX, 1e-6);
    // An explicit aspect ratio wins over the image's.
    Camera square = camera;
    square.aspectRatio = 1;
    const Vec3d right = directionOf(primaryRay(square, width, height, width, height / 2.0));
    EXPECT_NEAR(std::atan2(right.x, -right.z), halfY, 1e-6);
}

TEST(ImageCamera, RotatedCameraKeepsRightHandedFrame) {
    Camera camera = testCamera();
    camera.forward = {1, 0, 0};  // looking along +x, up +y: image right is +z
    const Vec3d right = directionOf(primaryRay(camera, 10, 10, 10, 5));
    EXPECT_GT(right.z, 0.1);
    EXPECT_NEAR(right.y, 0, 1e-7);
}

TEST(ImageCamera, ChooseByNameIndexOrDefault) {
    Scene scene;
    scene.path = "room.gltf";
    scene.mesh = verify::closedRoom({0, 0, 0}, {1, 1, 1});
    Camera a = testCamera(), b = testCamera();
    a.name = "front";
    b.name = "1";  // a name that is also an index: the name wins
    b.position = {5, 5, 5};
    scene.cameras = {a, b};
    EXPECT_EQ(chooseCamera(scene, "")->name, "front");
    EXPECT_EQ(chooseCamera(scene, "front")->name, "front");
    EXPECT_EQ(chooseCamera(scene, "0")->name, "front");
    EXPECT_EQ(chooseCamera(scene, "1")->position, Vec3d(5, 5, 5));
    const auto missing = chooseCamera(scene, "back");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("room.gltf"), std::string::npos);
    EXPECT_NE(missing.error().message.find("back"), std::string::npos);
    EXPECT_NE(missing.error().message.find("\"front\""), std::string::npos);
    EXPECT_FALSE(chooseCamera(scene, "2").ok());
    EXPECT_FALSE(chooseCamera(scene, "-1").ok());
    scene.cameras.clear();
    EXPECT_EQ(chooseCamera(scene, "")->name, "automatic");
    const auto none = chooseCamera(scene, "0");
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().message.find("no cameras"), std::string::npos);
}

TEST(ImageCamera, FramesAClosedRoomFromInside) {
    Scene scene;
    scene.mesh = verify::closedRoom({-1, 0, -2}, {3, 2, 2});  // 4 wide, 2 high, 4 deep
    const Camera camera = frameScene(scene, 1.5);
    EXPECT_EQ(camera.forward, Vec3d(0, 0, -1));
    EXPECT_EQ(camera.up, Vec3d(0, 1, 0));
    // Inside the box, near the z = 2 wall, centred on it.
    EXPECT_NEAR(camera.position.x, 1, 1e-12);
    EXPECT_NEAR(camera.position.y, 1, 1e-12);
    EXPECT_GT(camera.position.z, 1.8);
    EXPECT_LT(camera.position.z, 2);
    // The far wall (4 wide, 2 high at distance 3.92) fits: tan(yFov/2) >= (4 / 1.5 / 2) / 3.92.
    const double distance = camera.position.z + 2;
    EXPECT_GE(std::tan(camera.yFovRad / 2) + 1e-12, (4 / 1.5 / 2) / distance);
    EXPECT_GE(camera.yFovRad, 45 * kPi / 180 - 1e-12);
}

TEST(ImageCamera, FramesAnOpenSceneFromOutside) {
    Scene scene;
    // One quad facing +z: rays from its centre escape, so the camera stands outside.
    verify::addQuad(scene.mesh, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    const Camera camera = frameScene(scene, 2.0);
    EXPECT_EQ(camera.forward, Vec3d(0, 0, -1));
    const double radius = std::sqrt(2.0);
    // The bounding sphere fits the vertical field of view (the narrower one at aspect 2).
    EXPECT_NEAR(camera.position.z, radius / std::sin(camera.yFovRad / 2), 1e-9);
    EXPECT_NEAR(camera.yFovRad, 45 * kPi / 180, 1e-12);
    // A closed box whose faces point outwards is an object, not a room: also framed outside.
    Scene object;
    object.mesh = verify::closedRoom({0, 0, 0}, {1, 1, 1});
    for (auto& triangle : object.mesh.triangles)
        std::swap(triangle[1], triangle[2]);
    EXPECT_GT(frameScene(object, 1.0).position.z, 1);
}

TEST(ImageCamera, NumbersAreTheFilesCameraIndices) {
    // glTF cameras[] order, not the order the node tree reaches them; a skipped
    // orthographic camera's number says why it is missing.
    Scene scene;
    scene.path = "cams.gltf";
    scene.mesh = verify::closedRoom({0, 0, 0}, {1, 1, 1});
    Camera a = testCamera(), b = testCamera();
    a.name = "reached first";
    a.fileIndex = 1;
    b.name = "reached second";
    b.fileIndex = 0;
    scene.cameras = {a, b};
    scene.skippedCameras = {{2, "cameras[2] 'top' (orthographic)"}};
    EXPECT_EQ(chooseCamera(scene, "0")->name, "reached second");
    EXPECT_EQ(chooseCamera(scene, "1")->name, "reached first");
    EXPECT_EQ(chooseCamera(scene, "")->name, "reached first");  // the first in scene order
    const auto skipped = chooseCamera(scene, "2");
    ASSERT_FALSE(skipped.ok());
    EXPECT_EQ(skipped.error().message,
              "cams.gltf: camera 2 is cameras[2] 'top' (orthographic), which daisy skips (the "
              "scene's cameras are 1 \"reached first\", 0 \"reached second\")");
}

TEST(ImageCamera, FramesAnOpenModelFromTheFrontEvenWhenItIsDeep) {
    // glTF models face +z: a model deeper (z) than wide (x) is still seen from +z, not its side.
    Scene scene;
    verify::addSolidBox(scene.mesh, {-0.5, 0, -2}, {1, 1, 4});
    const Camera camera = frameScene(scene, 4.0 / 3);
    EXPECT_EQ(camera.forward, Vec3d(0, 0, -1));
    EXPECT_GT(camera.position.z, 2);
}

}  // namespace
}  // namespace daisy
