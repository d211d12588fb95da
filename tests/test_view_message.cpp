// The page messages of `yarnvox view` (src/view/view_message.h): what is
// accepted, field by field, and that every malformed or out-of-range message
// is refused with one line naming what is wrong.
#include "core/error.h"
#include "view/view_message.h"

#include <catch2/catch.hpp>

#include <string>
#include <variant>

using yv::parseViewMessage;

namespace {

std::string camera(const std::string& azimuth, const std::string& extra = "") {
    return R"({"type":"camera","azimuth":)" + azimuth + R"(,"elevation":20,"distance":4,"panX":0.5,"panY":-1,"seq":7)" +
           extra + "}";
}

} // namespace

TEST_CASE("View messages: a camera message is read field by field", "[view][message]") {
    const yv::ViewMessage m = parseViewMessage(camera("-45.5"));
    const auto* c = std::get_if<yv::CameraMessage>(&m);
    REQUIRE(c);
    CHECK(c->camera.azimuth == -45.5);
    CHECK(c->camera.elevation == 20.0);
    CHECK(c->camera.distance == 4.0);
    CHECK(c->camera.panX == 0.5);
    CHECK(c->camera.panY == -1.0);
    CHECK(c->camera.seq == 7u);
}

TEST_CASE("View messages: mode, size and voxelize-view are read, and every kind formats back to itself", "[view][message]") {
    const yv::ViewMessage mode = parseViewMessage(R"({"type":"mode","mode":"half-angle"})");
    REQUIRE(std::get_if<yv::ModeMessage>(&mode));
    CHECK(std::get<yv::ModeMessage>(mode).mode == "half-angle");
    const yv::ViewMessage size = parseViewMessage(R"({"type":"size","width":1280,"height":720})");
    REQUIRE(std::get_if<yv::SizeMessage>(&size));
    CHECK(std::get<yv::SizeMessage>(size).width == 1280);
    CHECK(std::get<yv::SizeMessage>(size).height == 720);
    CHECK(std::holds_alternative<yv::VoxelizeViewMessage>(parseViewMessage(R"({"type":"voxelize-view"})")));
    const yv::ViewMessage layout = parseViewMessage(R"({"type":"layout","blend":true})");
    REQUIRE(std::get_if<yv::LayoutMessage>(&layout));
    CHECK(std::get<yv::LayoutMessage>(layout).blend);
    const yv::ViewMessage shot = parseViewMessage(R"({"type":"screenshot","width":4096,"height":2304})");
    REQUIRE(std::get_if<yv::ScreenshotMessage>(&shot));
    CHECK(std::get<yv::ScreenshotMessage>(shot).width == 4096);
    CHECK(std::get<yv::ScreenshotMessage>(shot).height == 2304);
    const yv::ViewMessage save = parseViewMessage(R"({"type":"save-view","workDir":true})");
    REQUIRE(std::get_if<yv::SaveViewMessage>(&save));
    CHECK(std::get<yv::SaveViewMessage>(save).workDir);
    CHECK(!std::get<yv::SaveViewMessage>(parseViewMessage(R"({"type":"save-view"})")).workDir);
    for (const yv::ViewMessage& m :
         {parseViewMessage(camera("12.25")), mode, size, parseViewMessage(R"({"type":"voxelize-view"})"), save, shot, layout}) {
        const std::string text = yv::formatViewMessage(m);
        CHECK(yv::formatViewMessage(parseViewMessage(text)) == text);
    }
    const auto again = parseViewMessage(yv::formatViewMessage(parseViewMessage(camera("12.25"))));
    CHECK(std::get<yv::CameraMessage>(again).camera == std::get<yv::CameraMessage>(parseViewMessage(camera("12.25"))).camera);
}

TEST_CASE("View messages: malformed or hostile messages are refused with what is wrong", "[view][message]") {
    using Catch::Contains;
    CHECK_THROWS_WITH(parseViewMessage("not json"), Contains("not JSON"));
    CHECK_THROWS_WITH(parseViewMessage(""), Contains("not JSON"));
    CHECK_THROWS_WITH(parseViewMessage("[1,2]"), Contains("not a JSON object"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"kind":"camera"})"), Contains("without a string 'type'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":7})"), Contains("without a string 'type'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"shutdown"})"), Contains("unknown type 'shutdown'"));
    CHECK_THROWS_WITH(parseViewMessage(std::string(R"({"type":")") + std::string(5000, 'x') + "\"}"),
                      Contains("bytes (at most 1024)"));
    // Numbers: present, numeric, finite, in range, whole where they count.
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"camera","azimuth":1})"), Contains("needs the field 'elevation'"));
    CHECK_THROWS_WITH(parseViewMessage(camera("\"30\"")), Contains("'azimuth' of a 'camera' message must be a number"));
    CHECK_THROWS_AS(parseViewMessage(camera("1e999")), yv::Error); // an overflow: refused as JSON or as out of range
    CHECK_THROWS_WITH(parseViewMessage(camera("1e300")), Contains("'azimuth'") && Contains("must lie in"));
    CHECK_THROWS_WITH(parseViewMessage(camera("NaN")), Contains("not JSON"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"camera","azimuth":0,"elevation":91,"distance":4,"panX":0,"panY":0,"seq":1})"),
                      Contains("'elevation'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"camera","azimuth":0,"elevation":0,"distance":0,"panX":0,"panY":0,"seq":1})"),
                      Contains("'distance'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"camera","azimuth":0,"elevation":0,"distance":1,"panX":0,"panY":0,"seq":1.5})"),
                      Contains("'seq'") && Contains("whole number"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"camera","azimuth":0,"elevation":0,"distance":1,"panX":0,"panY":0,"seq":-1})"),
                      Contains("'seq'"));
    CHECK_THROWS_WITH(parseViewMessage(camera("0", R"(,"admin":true)")), Contains("no field 'admin'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"size","width":8,"height":720})"), Contains("'width'") && Contains("[16, 4096]"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"size","width":100000,"height":720})"), Contains("'width'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"size","width":640.5,"height":720})"), Contains("whole number"));
    // Strings: short, of known characters.
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"mode","mode":""})"), Contains("1 to 32 characters"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"mode","mode":"../../etc"})"), Contains("only a-z and '-'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"mode","mode":3})"), Contains("string field 'mode'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"voxelize-view","box":[0,0,0]})"), Contains("no field 'box'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"save-view","workDir":"yes"})"), Contains("'workDir' must be true or false"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"save-view","path":"/etc/passwd"})"), Contains("no field 'path'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"layout","blend":"yes"})"), Contains("'blend' must be true or false"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"layout"})"), Contains("needs 'blend', true or false"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"screenshot","width":8192,"height":4096})"),
                      Contains("screenshot") && Contains("'width'") && Contains("[16, 4096]"));
    // Deep nesting within the size cap is refused as not an object, not a crash.
    CHECK_THROWS_WITH(parseViewMessage(std::string(500, '[') + std::string(500, ']')), Contains("not a JSON object"));
}

TEST_CASE("View messages: a field name of control bytes is shown printable in the refusal", "[view][message]") {
    try {
        parseViewMessage("{\"type\":\"size\",\"w\\u0001\\u001b[2J\":1}");
        FAIL("accepted");
    } catch (const yv::Error& e) {
        const std::string what = e.what();
        for (char ch : what) CHECK((ch >= 0x20 && ch <= 0x7e));
    }
}

TEST_CASE("View messages: transfer and twist are read within their limits and format back to themselves", "[view][message]") {
    using Catch::Contains;
    const yv::ViewMessage transfer = parseViewMessage(R"({"type":"transfer","preset":"heat","opacity":2.5})");
    REQUIRE(std::get_if<yv::TransferMessage>(&transfer));
    CHECK(std::get<yv::TransferMessage>(transfer).preset == "heat");
    CHECK(std::get<yv::TransferMessage>(transfer).opacity == 2.5);
    const yv::ViewMessage twist = parseViewMessage(R"({"type":"twist","twist":-3.25})");
    REQUIRE(std::get_if<yv::TwistMessage>(&twist));
    CHECK(std::get<yv::TwistMessage>(twist).twist == -3.25);
    for (const yv::ViewMessage& m : {transfer, twist}) {
        const std::string text = yv::formatViewMessage(m);
        CHECK(yv::formatViewMessage(parseViewMessage(text)) == text);
    }
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"transfer","preset":"heat"})"), Contains("needs the field 'opacity'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"transfer","preset":"heat","opacity":0})"),
                      Contains("'opacity'") && Contains("must lie in [0.015625, 64]"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"transfer","preset":"heat","opacity":65})"), Contains("'opacity'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"transfer","preset":"/tmp/map.txt","opacity":1})"),
                      Contains("preset may hold only a-z and '-'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"transfer","preset":"heat","opacity":1,"file":"x"})"), Contains("no field 'file'"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"twist","twist":1e5})"), Contains("'twist'") && Contains("[-10000, 10000]"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"twist","twist":"3"})"), Contains("must be a number"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"twist"})"), Contains("needs the field 'twist'"));
}

TEST_CASE("View messages: a camera says whether it is moving, and quality whether moving frames may degrade",
          "[view][message]") {
    using Catch::Contains;
    CHECK_FALSE(std::get<yv::CameraMessage>(parseViewMessage(camera("0"))).moving);
    CHECK(std::get<yv::CameraMessage>(parseViewMessage(camera("0", R"(,"moving":true)"))).moving);
    CHECK_FALSE(std::get<yv::CameraMessage>(parseViewMessage(camera("0", R"(,"moving":false)"))).moving);
    const yv::ViewMessage quality = parseViewMessage(R"({"type":"quality","degrade":false})");
    REQUIRE(std::get_if<yv::QualityMessage>(&quality));
    CHECK_FALSE(std::get<yv::QualityMessage>(quality).degrade);
    CHECK(std::get<yv::QualityMessage>(parseViewMessage(R"({"type":"quality","degrade":true})")).degrade);
    for (const yv::ViewMessage& m : {parseViewMessage(camera("5", R"(,"moving":true)")), quality}) {
        const std::string text = yv::formatViewMessage(m);
        CHECK(yv::formatViewMessage(parseViewMessage(text)) == text);
    }
    CHECK(std::get<yv::CameraMessage>(parseViewMessage(yv::formatViewMessage(parseViewMessage(camera("5", R"(,"moving":true)")))))
              .moving);
    CHECK_THROWS_WITH(parseViewMessage(camera("0", R"(,"moving":1)")), Contains("'moving' must be true or false"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"quality"})"), Contains("needs 'degrade', true or false"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"quality","degrade":"no"})"), Contains("'degrade' must be true or false"));
    CHECK_THROWS_WITH(parseViewMessage(R"({"type":"quality","degrade":false,"fps":5})"), Contains("no field 'fps'"));
}
