#include "loosehair/json_checks.hpp"

#include <algorithm>

#include <nlohmann/json.hpp>

#include <set>
#include <vector>

namespace loosehair {
namespace {

using json = nlohmann::json;

// A SAX pass that builds nothing: it follows the nesting and the keys.
class Checker : public nlohmann::json_sax<json> {
 public:
  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(true); }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(false); }
  bool end_array() override { return close(); }
  bool key(string_t& k) override {
    Level& level = stack_.back();
    if (!level.keys.insert(k).second) {
      problem_ = pathWith(k) + ": the key \"" + clipped(k) + "\" appears twice in one object";
      return false;
    }
    level.key = k;
    return true;
  }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
    // the library's own words, without its "[json.exception...] " tag
    std::string what = e.what();
    if (const std::size_t tag = what.find("] "); what.rfind("[json.exception", 0) == 0 && tag != std::string::npos)
      what = what.substr(tag + 2);
    position_ = position;
    syntax_ = true;
    problem_ = clipped(what, 200);
    return false;
  }

  const std::string& problem() const { return problem_; }
  std::size_t position() const { return position_; }
  bool syntax() const { return syntax_; }

 private:
  std::size_t position_ = 0;
  bool syntax_ = false;  // a syntax error (else nesting or a repeated key)
  struct Level {
    bool object;
    std::set<std::string> keys;
    std::string key;        // the current key (objects)
    std::size_t index = 0;  // the current element (arrays)
  };

  bool value() {
    if (!stack_.empty() && !stack_.back().object) ++stack_.back().index;
    return true;
  }
  bool open(bool object) {
    if (static_cast<int>(stack_.size()) >= kMaxJsonDepth) {
      problem_ = clipped(stack_.empty() ? std::string("the top level") : path(), 80) + ": nested more than " +
                 std::to_string(kMaxJsonDepth) + " levels deep";
      return false;
    }
    stack_.push_back(Level{object, {}, {}, 0});
    return true;
  }
  bool close() {
    stack_.pop_back();
    return value();
  }
  // The path of the current value: levels [0, depth) of the stack.
  std::string path(std::size_t depth) const {
    std::string p;
    for (std::size_t d = 0; d < depth; ++d) {
      const Level& l = stack_[d];
      if (l.object) {
        if (l.key.empty()) continue;
        if (!p.empty()) p.push_back('.');
        p.append(clipped(l.key, 40));
      } else {
        p.push_back('[');
        p.append(std::to_string(l.index));
        p.push_back(']');
      }
    }
    return p;
  }
  std::string path() const {
    std::string p = path(stack_.size());
    return p.empty() ? std::string("the top level") : p;
  }
  // The repeated key `k` of the innermost object.
  std::string pathWith(const std::string& k) const {
    std::string p = path(stack_.size() - 1);
    if (!p.empty()) p.push_back('.');
    p.append(clipped(k, 40));
    return p;
  }

  std::vector<Level> stack_;
  std::string problem_;
};

}  // namespace

std::string clipped(std::string_view text, std::size_t limit) {
  if (text.size() <= limit) return std::string(text);
  return std::string(text.substr(0, limit > 3 ? limit - 3 : 0)) + "... (" + std::to_string(text.size()) +
         " characters)";
}

void checkJson(std::string_view text, const std::string& source, void (*raise)(const std::string& message)) {
  Checker checker;
  const bool ok = json::sax_parse(text.begin(), text.end(), &checker, json::input_format_t::json,
                                  /*strict=*/true);
  if (ok) return;
  if (!checker.problem().empty() && !checker.syntax()) raise(source + ": " + checker.problem());
  // not JSON at all (a mesh or an image given for a scene, say): say so
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) raise(source + ": the file is empty; a JSON object {...} was expected");
  if (text[first] != '{' && text[first] != '[') {
    std::string start;
    for (std::size_t k = first; k < text.size() && start.size() < 12; ++k) {
      const unsigned char c = static_cast<unsigned char>(text[k]);
      if (c == '\n' || c == '\r') break;
      start += c >= 32 && c < 127 ? static_cast<char>(c) : '?';
    }
    raise(source + ": is not a JSON file (it begins with \"" + start + "\"); a JSON object {...} was expected");
  }
  if (checker.problem().empty()) raise(source + ": invalid JSON");
  // where, as an editor shows it
  const std::size_t at = std::min(checker.position(), text.size());
  std::size_t line = 1, column = 1;
  for (std::size_t k = 0; k + 1 < at; ++k) {
    if (text[k] == '\n')
      ++line, column = 1;
    else
      ++column;
  }
  raise(source + ": invalid JSON at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " +
        checker.problem());
}

}  // namespace loosehair
