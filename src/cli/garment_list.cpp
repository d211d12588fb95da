#include "cli/garment_list.h"

#include "core/error.h"

#include <filesystem>
#include <fstream>
#include <map>

namespace yv {
namespace {

namespace fs = std::filesystem;

std::string trimmed(const std::string& s) {
    const auto first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos) return "";
    return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

void makeDirectory(const std::string& dir, const std::string& what) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw Error(what + " " + dir + ": with several garments this names a directory, and it cannot be made" +
                    (ec ? " (" + ec.message() + ")" : std::string(" (a file is in the way)")));
}

} // namespace

std::vector<std::string> readGarmentList(const std::string& listPath) {
    std::ifstream in(listPath);
    if (!in) throw Error("--list " + listPath + ": cannot open it");
    const fs::path base = fs::path(listPath).parent_path();
    std::vector<std::string> paths;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const std::string text = trimmed(line);
        if (text.empty() || text[0] == '#') continue;
        const fs::path p = fs::path(text).is_absolute() ? fs::path(text) : base / text;
        std::error_code ec;
        if (!fs::is_regular_file(p, ec))
            throw Error("--list " + listPath + ", line " + std::to_string(number) + ": " + p.string() +
                        " is not a garment file");
        paths.push_back(p.string());
    }
    if (paths.empty()) throw Error("--list " + listPath + ": names no garment");
    return paths;
}

std::vector<GarmentJob> planGarmentJobs(const std::vector<std::string>& inputs, const std::string& outputDir,
                                        const std::string& extension, const std::string& workDirRoot,
                                        const std::string& statsDir) {
    std::map<std::string, std::string> inputOfStem;
    std::vector<GarmentJob> jobs;
    for (const std::string& input : inputs) {
        const std::string stem = fs::path(input).stem().string();
        if (const auto [at, fresh] = inputOfStem.emplace(stem, input); !fresh)
            throw Error(input + " and " + at->second + " would both write " +
                        (fs::path(outputDir) / (stem + extension)).string() + ": rename one of them");
        GarmentJob job;
        job.input = input;
        job.output = (fs::path(outputDir) / (stem + extension)).string();
        if (!workDirRoot.empty()) job.workDir = (fs::path(workDirRoot) / stem).string();
        if (!statsDir.empty()) job.statsPath = (fs::path(statsDir) / (stem + ".json")).string();
        jobs.push_back(job);
    }
    makeDirectory(outputDir, "-o");
    if (!workDirRoot.empty()) makeDirectory(workDirRoot, "--work-dir");
    if (!statsDir.empty()) makeDirectory(statsDir, "--stats");
    return jobs;
}

} // namespace yv
