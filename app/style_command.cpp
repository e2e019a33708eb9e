#include "style_command.hpp"

#include "cli_args.hpp"
#include "loosehair/file_io.hpp"
#include "loosehair/groom_import.hpp"
#include "loosehair/strand_files.hpp"
#include "loosehair/style.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <utility>

namespace loosehair::app {

const char* const kStyleUsage =
    "usage: loosehair style STYLE.json [--strands OUT] [--spacing MM] [--allow-expensive]\n"
    "       loosehair style --import GROOM --head FILE.json --out STYLE.json\n"
    "                       [--scale S] [--max-root-distance MM] [--strands OUT]\n"
    "\n"
    "  Builds a style's member strands, checks the style against its head and\n"
    "  prints its wisp, strand and point counts.\n"
    "    --strands OUT    write the strands as polylines, head frame in metres:\n"
    "                     OUT.obj (v and l elements), OUT.ply (vertex and edge\n"
    "                     elements) or OUT.hair (cyHair binary), by extension\n"
    "    --spacing MM     distance between the points of a strand (default 4 mm)\n"
    "    --allow-expensive  build styles of more than 5 million strands or 50\n"
    "                     million points, or on meshes of more than 10 million\n"
    "                     triangles (refused by default, saying what to change)\n"
    "\n"
    "  --import reads a groom made elsewhere (.hair, or OBJ/PLY polylines) and\n"
    "  writes a style with one wisp a strand, rooted on the head of FILE.json\n"
    "  (a scene or a style file), ready for \"hair\": {\"style\": ...} in a scene\n"
    "  or for simulate --style.\n"
    "    --scale S        multiply the groom's coordinates by S first (e.g. 0.01\n"
    "                     for centimetres); default 1 (metres, head frame)\n"
    "    --max-root-distance MM  leave out strands whose root is farther than\n"
    "                     this from the scalp (default 20 mm)\n";

namespace {

struct StyleOptions {
  std::string style, groom, head, out, strands;
  double spacing_mm = 4.0, scale = 1.0, max_root_mm = 20.0;
  bool allow_expensive = false;
};

StyleOptions parse(const std::vector<std::string>& args) {
  StyleOptions o;
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    auto value = [&]() -> const std::string& {
      if (k + 1 >= args.size()) throw UsageError{a + " needs a value", kStyleUsage};
      return args[++k];
    };
    if (a == "--strands")
      o.strands = value();
    else if (a == "--spacing")
      o.spacing_mm = parseReal(a, value(), 0.1, 100.0, kStyleUsage);
    else if (a == "--import")
      o.groom = value();
    else if (a == "--allow-expensive")
      o.allow_expensive = true;
    else if (a == "--head")
      o.head = value();
    else if (a == "--out")
      o.out = value();
    else if (a == "--scale")
      o.scale = parseReal(a, value(), 1e-6, 1e6, kStyleUsage);
    else if (a == "--max-root-distance")
      o.max_root_mm = parseReal(a, value(), 0.01, 1000.0, kStyleUsage);
    else if (!a.empty() && a[0] == '-')
      throw unknownOption(a, kStyleUsage);
    else if (o.style.empty())
      o.style = a;
    else
      throw UsageError{"more than one style given: '" + o.style + "' and '" + a + "'", kStyleUsage};
  }
  if (!o.groom.empty()) {
    if (!o.style.empty())
      throw UsageError{"--import makes a style: give it --out STYLE.json, not '" + o.style + "'", kStyleUsage};
    if (o.head.empty()) throw UsageError{"--import needs --head FILE.json (a scene or style file)", kStyleUsage};
    if (o.out.empty()) throw UsageError{"--import needs --out STYLE.json", kStyleUsage};
  } else {
    if (o.style.empty()) throw UsageError{"style needs a style file (or --import GROOM)", kStyleUsage};
    if (!o.head.empty() || !o.out.empty())
      throw UsageError{std::string(o.head.empty() ? "--out" : "--head") + " is for --import", kStyleUsage};
  }
  return o;
}

// The head of a scene or style file: a style file is the one with "wisps".
HeadDesc headOf(const std::string& path) {
  const std::string text = readRegularFile(path, kMaxTextFileBytes);
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_object() && j.contains("wisps")) return loadStyle(path).head;
  return loadScene(path);
}

void report(const Style& style, const StrandSet& strands, double seconds) {
  std::printf("style: %s (%s)\n", style.name.c_str(), style.source.c_str());
  std::printf("wisps: %zu, ties: %zu, strands: %zu, points: %zu (built in %.2f s)\n", style.wisps.size(),
              style.ties.size(), strands.size(), strands.points.size(), seconds);
}

// Whether `a` and `b` name the same file (the same inode where both exist,
// else the same normalised absolute path).
bool sameFile(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) {
    const bool same = fs::equivalent(a, b, ec);
    if (!ec) return same;
  }
  return fs::weakly_canonical(fs::absolute(a), ec) == fs::weakly_canonical(fs::absolute(b), ec);
}

// Refuses an output that is one of the inputs, or both outputs the same file.
void checkOutputsAreNotInputs(const StyleOptions& o) {
  std::vector<std::pair<std::string, std::string>> inputs = {{"--import", o.groom}, {"--head", o.head}};
  std::vector<std::pair<std::string, std::string>> outputs = {{"--out", o.out}};
  if (!o.strands.empty()) outputs.push_back({"--strands", o.strands});
  for (const auto& [oflag, out] : outputs)
    for (const auto& [iflag, in] : inputs)
      if (sameFile(out, in))
        throw UsageError{oflag + " " + out + " is the file given to " + iflag +
                             "; it would be overwritten. "
                             "Choose another name for the output",
                         kStyleUsage};
  if (outputs.size() == 2 && sameFile(o.out, o.strands))
    throw UsageError{"--out and --strands name the same file (" + o.out + ")", kStyleUsage};
}

void writeOut(const StrandSet& strands, const std::string& path) {
  writeStrands(strands, path);
  std::printf("strands written: %s\n", path.c_str());
}

}  // namespace

int styleCommand(const std::vector<std::string>& args) {
  const StyleOptions o = parse(splitFlagValues(args));
  using Clock = std::chrono::steady_clock;
  const float spacing = static_cast<float>(o.spacing_mm * 1e-3);
  const StrandBudget budget = o.allow_expensive ? StrandBudget::unlimited() : StrandBudget{};
  const MeshLimits mesh_limits = o.allow_expensive ? MeshLimits::unlimited() : MeshLimits{};
  if (o.groom.empty()) {
    const Style style = loadStyle(o.style);
    const HeadModel head = HeadModel::build(style.head, style.source, mesh_limits);
    checkStyle(style, head);
    const auto t0 = Clock::now();
    const StrandSet strands = buildMemberStrands(style, head, spacing, budget);
    report(style, strands, std::chrono::duration<double>(Clock::now() - t0).count());
    if (!o.strands.empty()) writeOut(strands, o.strands);
    return 0;
  }
  checkOutputsAreNotInputs(o);
  (void)checkOutputTarget(o.out);
  if (!o.strands.empty()) (void)checkOutputTarget(o.strands);
  const HeadDesc desc = headOf(o.head);
  const HeadModel head = HeadModel::build(desc, o.head, mesh_limits);
  const Polylines groom = readPolylines(o.groom);
  GroomImportOptions opt;
  opt.scale = static_cast<float>(o.scale);
  opt.max_root_distance = static_cast<float>(o.max_root_mm * 1e-3);
  GroomImportReport rep;
  Style style = importGroom(groom, desc, head, o.groom, opt, &rep);
  std::printf("groom: %s: %zu strands read, %zu kept (root up to %.1f mm from the scalp)", o.groom.c_str(),
              rep.strands_read, rep.strands_kept, rep.largest_root_distance * 1e3);
  if (rep.skipped_far) std::printf(", %zu left out (root too far from the scalp)", rep.skipped_far);
  if (rep.skipped_short) std::printf(", %zu left out (fewer than two points)", rep.skipped_short);
  if (rep.skipped_beyond)
    std::printf(", %zu left out (reaching beyond %.0f m)", rep.skipped_beyond, double(kMaxStyleCoordinate));
  if (rep.reversed) std::printf(", %zu stored tip first", rep.reversed);
  std::printf("\n");
  checkStyle(style, head);
  // What is written must load: the text is read back as the style reader
  // reads a file, within the size a style file may have.
  const std::string text = styleText(style, o.out);
  if (text.size() > kMaxTextFileBytes)
    throw StyleError(o.out + ": the imported style would be " + std::to_string(text.size() >> 20) +
                     " MiB, more than the " + std::to_string(kMaxTextFileBytes >> 20) +
                     " MiB a style file may be; nothing was written (import fewer strands: " +
                     std::to_string(style.wisps.size()) + " were kept)");
  Style check = parseStyle(text, o.out);
  checkStyle(check, head);
  style.source = o.out;
  const auto t0 = Clock::now();
  const StrandSet strands = buildMemberStrands(style, head, spacing, budget);
  report(style, strands, std::chrono::duration<double>(Clock::now() - t0).count());
  // Both files or neither: everything is written to temporaries first and
  // renamed only when both are complete.
  AtomicFile style_file(o.out);
  style_file.write(text);
  std::optional<AtomicFile> strand_file;
  if (!o.strands.empty()) {
    Polylines lines;
    lines.points = strands.points;
    lines.first = strands.first;
    const std::string bytes = polylineFileBytes(lines, o.strands);
    strand_file.emplace(o.strands);
    strand_file->write(bytes);
    strand_file->finish();
  }
  style_file.finish();
  style_file.commit();
  std::printf("style written: %s\n", o.out.c_str());
  if (strand_file) {
    strand_file->commit();
    std::printf("strands written: %s\n", o.strands.c_str());
  }
  return 0;
}

}  // namespace loosehair::app
