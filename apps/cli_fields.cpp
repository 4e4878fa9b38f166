#include "apps/cli_fields.hpp"

namespace cleanmap::app {
using namespace ::cleanmap::pipeline;

CLI::Validator number_in(const Range& r) {
  return CLI::Validator(
      [r](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        return check_value(v, r);
      },
      "NUMBER " + pipeline::describe(r));
}

void add_output_options(CLI::App& cmd, std::filesystem::path& out, bool& overwrite, const std::string& help) {
  cmd.add_option("--out", out, help)->capture_default_str();
  cmd.add_flag("--overwrite", overwrite,
               "Replace an earlier cleanmap output in --out (its files are removed first); without it a "
               "non-empty --out is refused");
}

}  // namespace cleanmap::app
