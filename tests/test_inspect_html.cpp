// `yarnvox inspect --html DIR`: the report of a work directory and of a
// .vdb, loaded in headless Chromium with a probe that checks every image
// loads, every link target exists and the page logs no error.
#include "run_cli.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace fs = std::filesystem;

namespace {

struct Scratch : yv::test::ScratchDir {
    Scratch() : yv::test::ScratchDir("yv_test_html") {}
};

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Runs before the page's own content (errors of any kind are caught from
/// the start) and, once the page has loaded, writes one line into the DOM:
/// how many images and links it has and every problem found.
constexpr const char* kProbe = R"(<script>
window.__problems = [];
addEventListener('error', e => __problems.push('error: ' + (e.message || (e.target && (e.target.src || e.target.href)) || '?')), true);
const __consoleError = console.error;
console.error = (...a) => { __problems.push('console.error: ' + a.join(' ')); __consoleError(...a); };
addEventListener('load', async () => {
  for (const img of document.images)
    if (!(img.complete && img.naturalWidth > 0)) __problems.push('image did not load: ' + img.getAttribute('src'));
  const links = Array.from(document.querySelectorAll('a'));
  // Every link of the report goes to a row of its own (#id) or to a PNG beside it.
  await Promise.all(links.map(a => new Promise(done => {
    const href = a.getAttribute('href') || '';
    if (href.startsWith('#')) {
      if (!document.getElementById(href.slice(1))) __problems.push('no element for link ' + href);
      return done();
    }
    const i = new Image();
    i.onload = () => done();
    i.onerror = () => { __problems.push('link target does not load: ' + href); done(); };
    i.src = href;
  })));
  const out = document.createElement('pre');
  // Spelled apart so that the script's own text in the dumped DOM never matches.
  out.textContent = 'PRO' + 'BE images=' + document.images.length + ' links=' + links.length +
                    ' problems=' + JSON.stringify(__problems) + ' END';
  document.body.appendChild(out);
});
</script>)";

struct ProbeResult {
    int images = -1, links = -1;
    std::string problems; ///< a JSON list; "[]" when the page is sound
    std::string output;   ///< all Chromium printed, for failures
};

/// Loads `report`/index.html in headless Chromium (as the README's setup
/// installs it) through a copy that carries the probe above.
ProbeResult probeReport(const fs::path& report, const fs::path& scratch) {
    if (yv::test::runShell("command -v chromium").exitCode != 0)
        FAIL("chromium is not installed: run tools/setup (the HTML report is tested in headless Chromium)");
    std::string page = readText(report / "index.html");
    const std::size_t head = page.find("<head>");
    REQUIRE(head != std::string::npos);
    page.insert(head + 6, "<base href=\"file://" + fs::absolute(report).string() + "/\">" + kProbe);
    const fs::path probe = scratch / "probe.html";
    std::ofstream(probe) << page;
    const fs::path profile = scratch / "chromium-profile";
    const yv::test::RunResult r = yv::test::runShell(
        "chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking "
        "--disable-component-update --disable-sync --user-data-dir=" + profile.string() +
        " --virtual-time-budget=10000 --dump-dom file://" + fs::absolute(probe).string());
    ProbeResult p;
    p.output = r.output;
    const std::size_t at = r.output.find("PROBE images=");
    const std::size_t end = r.output.find(" END", at);
    if (r.exitCode != 0 || at == std::string::npos || end == std::string::npos) return p;
    std::istringstream line(r.output.substr(at, end - at));
    std::string word;
    line >> word; // PROBE
    line >> word;
    p.images = std::stoi(word.substr(7));
    line >> word;
    p.links = std::stoi(word.substr(6));
    std::getline(line >> std::ws, word);
    p.problems = word.substr(9);
    return p;
}

std::size_t filesIn(const fs::path& dir) {
    return std::size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

/// A small generated garment voxelized into a work directory of several regions, and its .vdb.
void voxelizeSmallGarment(const fs::path& scratch) {
    const fs::path bcc = scratch / "knit.bcc";
    REQUIRE(yv::test::runYarnvox("gen --pattern knit --crossings 20 --shape cylinder --seed 3 -o " + bcc.string()).exitCode == 0);
    const yv::test::RunResult v =
        yv::test::runYarnvox("voxelize " + bcc.string() + " -o " + (scratch / "knit.vdb").string() +
                             " --backend cpu --resolution 64 --fragment-budget 12000 --quiet --work-dir " +
                             (scratch / "work").string());
    INFO(v.output);
    REQUIRE(v.exitCode == 0);
}

} // namespace

TEST_CASE("inspect --html of a work dir loads in Chromium with every image and link", "[inspect][html]") {
    YV_REQUIRE_GL();
    Scratch scratch;
    voxelizeSmallGarment(scratch.path);
    const fs::path work = scratch.path / "work", report = scratch.path / "report";
    const std::size_t regions = filesIn(work) - 1; // less the manifest
    REQUIRE(regions > 2);

    const yv::test::RunResult r = yv::test::runYarnvox("inspect " + work.string() + " --html " + report.string() +
                                                       " --html-renders 2 --size 160x120");
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("renders of 2 of " + std::to_string(regions) + " regions") != std::string::npos);
    // Three whole-volume renders (ray cast, MIP, orientation) and the two hottest regions', nothing left over.
    CHECK(filesIn(report / "renders") == 5);
    CHECK(filesIn(scratch.path) == 4); // knit.bcc, knit.vdb, work, report: no temporary left
    const std::string page = readText(report / "index.html");
    CHECK(page.find("the 2 hottest of " + std::to_string(regions) + " regions") != std::string::npos);
    CHECK(page.find("Time per stage") != std::string::npos);
    CHECK(page.find("Not recorded") == std::string::npos);
    CHECK(page.find("http") == std::string::npos); // self-contained: no external address
    for (std::size_t id = 0; id < regions; ++id)
        CHECK(page.find("<tr id=\"region-" + std::to_string(id) + "\">") != std::string::npos);

    const ProbeResult p = probeReport(report, scratch.path);
    INFO(p.output);
    CHECK(p.problems == "[]");
    CHECK(p.images == 2 + 3 + 0);           // region thumbnails and whole-volume renders
    CHECK(p.links >= int(regions) + 5);     // every region on the map, and every picture

    // The probe can fail: a picture gone is reported, by its image and its link.
    fs::remove(report / "renders" / "volume-mip.png");
    const ProbeResult broken = probeReport(report, scratch.path);
    INFO(broken.output);
    CHECK(broken.problems.find("image did not load: renders/volume-mip.png") != std::string::npos);
    CHECK(broken.problems.find("link target does not load: renders/volume-mip.png") != std::string::npos);
}

TEST_CASE("inspect --html of a .vdb maps the regions it records, and one that records none says so", "[inspect][html]") {
    YV_REQUIRE_GL();
    Scratch scratch;
    voxelizeSmallGarment(scratch.path);
    const std::size_t regions = filesIn(scratch.path / "work") - 1; // less the manifest
    REQUIRE(regions > 2);
    const fs::path report = scratch.path / "vdb-report";
    const yv::test::RunResult r = yv::test::runYarnvox("inspect " + (scratch.path / "knit.vdb").string() + " --html " +
                                                       report.string() + " --html-renders 2 --size 160x120");
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("renders of 2 of " + std::to_string(regions) + " regions") != std::string::npos);
    const std::string page = readText(report / "index.html");
    CHECK(page.find("the 2 hottest of " + std::to_string(regions) + " regions") != std::string::npos);
    CHECK(page.find("Not recorded (the file has no stage_seconds metadata") != std::string::npos);
    for (std::size_t id = 0; id < regions; ++id)
        CHECK(page.find("<tr id=\"region-" + std::to_string(id) + "\">") != std::string::npos);
    CHECK(filesIn(report / "renders") == 3 + 2);
    const ProbeResult p = probeReport(report, scratch.path);
    INFO(p.output);
    CHECK(p.problems == "[]");
    CHECK(p.images == 3 + 2);
    CHECK(p.links >= int(regions) + 5);

    // Without the record (the dense method writes none): the whole volume only, and the page says why.
    const fs::path dense = scratch.path / "dense.vdb", plain = scratch.path / "plain-report";
    const yv::test::RunResult d = yv::test::runYarnvox("voxelize " + (scratch.path / "knit.bcc").string() + " -o " +
                                                       dense.string() + " --method dense --resolution 48 --quiet");
    INFO(d.output);
    REQUIRE(d.exitCode == 0);
    const yv::test::RunResult q = yv::test::runYarnvox("inspect " + dense.string() + " --html " + plain.string() +
                                                       " --size 160x120");
    INFO(q.output);
    REQUIRE(q.exitCode == 0);
    CHECK(readText(plain / "index.html").find("The file has no zoom regions") != std::string::npos);
    CHECK(filesIn(plain / "renders") == 3);
    const ProbeResult pp = probeReport(plain, scratch.path);
    INFO(pp.output);
    CHECK(pp.problems == "[]");
    CHECK(pp.images == 3);
}

TEST_CASE("inspect --html leaves no report behind when it fails and never replaces a foreign directory", "[inspect][html]") {
    YV_REQUIRE_GL();
    Scratch scratch;
    voxelizeSmallGarment(scratch.path);
    const fs::path work = scratch.path / "work", report = scratch.path / "report";

    // A render that cannot be made (no such EGL device) fails the report: no DIR, no temporary.
    const yv::test::RunResult failed =
        yv::test::runYarnvox("inspect " + work.string() + " --html " + report.string() + " --device 99");
    INFO(failed.output);
    CHECK(failed.exitCode != 0);
    CHECK_FALSE(fs::exists(report));
    CHECK(filesIn(scratch.path) == 3);

    // A directory with someone else's files is refused and left as it was.
    fs::create_directories(report);
    std::ofstream(report / "notes.txt") << "mine\n";
    const yv::test::RunResult refused = yv::test::runYarnvox("inspect " + work.string() + " --html " + report.string());
    INFO(refused.output);
    CHECK(refused.exitCode != 0);
    CHECK(refused.output.find("not a yarnvox report") != std::string::npos);
    CHECK(filesIn(report) == 1);

    // An earlier report is replaced whole.
    fs::remove_all(report);
    const std::string args = "inspect " + work.string() + " --html " + report.string() + " --html-renders 0 --size 64x48";
    REQUIRE(yv::test::runYarnvox(args).exitCode == 0);
    std::ofstream(report / "renders" / "stale.png") << "x";
    REQUIRE(yv::test::runYarnvox(args).exitCode == 0);
    CHECK_FALSE(fs::exists(report / "renders" / "stale.png"));
    CHECK(filesIn(report / "renders") == 3);
    CHECK(filesIn(scratch.path) == 4);
}
