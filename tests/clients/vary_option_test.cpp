// The parser of `granulab sweep --vary KEY=V1,V2,...` (clients/cli/vary_option.h): scalars as before, lists and
// objects as one value each, quoted text with commas, and every malformed option refused with a message that says
// what is wrong and shows the syntax. The CLI itself runs it against a daemon in remote_cli_test.py.
#include "clients/cli/vary_option.h"

#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace {

using granulab::cli::parse_vary;
using nlohmann::json;

json vary(const std::vector<std::string>& options, bool zip = false) { return parse_vary(options, zip); }

// The message of the refusal of `options`, or "" when they are taken.
std::string refusal(const std::vector<std::string>& options, bool zip = false) {
  try {
    parse_vary(options, zip);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(VaryOption, ScalarsAreSplitAtEveryCommaAsBefore) {
  EXPECT_EQ(vary({"loading.confining_pressure=10e3,30e3,60e3"}),
            json::parse(R"({"loading.confining_pressure": [10000.0, 30000.0, 60000.0]})"));
  EXPECT_EQ(vary({"material.friction=0.1,0.3", "grain.edge_spheres=2,3"}),
            json::parse(R"({"material.friction": [0.1, 0.3], "grain.edge_spheres": [2, 3]})"));
  // Plain text is a string, JSON text too; true, null and numbers are themselves.
  EXPECT_EQ(vary({"crystal.lattice=sc, fcc ,\"bcc\""})["crystal.lattice"], json::parse(R"(["sc", "fcc", "bcc"])"));
  EXPECT_EQ(vary({"a.b=true,null,-2"})["a.b"], json::parse("[true, null, -2]"));
  EXPECT_TRUE(vary({"grain.edge_spheres=3"})["grain.edge_spheres"][0].is_number_integer());
}

TEST(VaryOption, AListIsOneValue) {
  EXPECT_EQ(vary({"loading.axis=[1,1,0],[1,1,1]"})["loading.axis"], json::parse("[[1, 1, 0], [1, 1, 1]]"));
  EXPECT_EQ(vary({"loading.axis=[1, 1, 0], [2,-1,-1,0]"})["loading.axis"], json::parse("[[1, 1, 0], [2, -1, -1, 0]]"));
  // One list is one point, not a list of points.
  EXPECT_EQ(vary({"loading.axis=[1,1,0]"})["loading.axis"], json::parse("[[1, 1, 0]]"));
  EXPECT_EQ(vary({"output.snapshot_strains=[0,0.001],[],[0,0.002,0.004]"})["output.snapshot_strains"],
            json::parse("[[0, 0.001], [], [0, 0.002, 0.004]]"));
  // Nested lists and objects (a loading program), and commas and brackets inside quoted text.
  EXPECT_EQ(vary({R"(loading.program=[{"to_strain":0.01},{"hold_steps":10}],[{"to_strain":0.02}])"})["loading.program"],
            json::parse(R"([[{"to_strain": 0.01}, {"hold_steps": 10}], [{"to_strain": 0.02}]])"));
  EXPECT_EQ(vary({R"(label="a,b","c]\"d",e)"})["label"], json::parse(R"(["a,b", "c]\"d", "e"])"));
}

TEST(VaryOption, ZipNeedsListsOfOneLength) {
  EXPECT_EQ(vary({"loading.axis=[1,1,0],[1,1,1]", "crystal.lattice=sc,bcc"}, true).size(), 2u);
  const std::string e = refusal({"loading.axis=[1,1,0],[1,1,1]", "crystal.lattice=sc,bcc,fcc"}, true);
  EXPECT_NE(e.find("'loading.axis' has 2 values, 'crystal.lattice' has 3"), std::string::npos) << e;
  EXPECT_EQ(refusal({"loading.axis=[1,1,0],[1,1,1]", "crystal.lattice=sc,bcc,fcc"}), "");  // every combination
}

TEST(VaryOption, EveryMalformedOptionSaysWhatIsWrongAndShowsTheSyntax) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"loading.axis", "no '=' between the field and its values"},
      {"=1,2", "no field before the '='"},
      {"loading.axis=", "no values after the '='"},
      {"loading.axis[0]=1,2", "'loading.axis[0]' is not a dotted spec field"},
      {"loading..axis=1", "'loading..axis' is not a dotted spec field"},
      {"material.friction=0.1,,0.3", "value 2 of 3 is empty"},
      {"material.friction=0.1,0.3,", "value 3 of 3 is empty"},
      {"loading.axis=[1,1,0],[1,1,1", "a '[' is never closed"},
      {"loading.axis=[1,1,0]],[1,1,1]", "the ']' at character 8 of the values closes nothing"},
      {"loading.axis=[1,1,0},[1,1,1]", "the '}' at character 7 of the values should be a ']'"},
      {"crystal.lattice=\"sc,fcc", "a '\"' is never closed"},
      {"loading.axis=[1 1 0],[1,1,1]", "value 1 of 2, [1 1 0], is not JSON"},
      {"loading.axis=1,1,0]", "the ']' at character 6 of the values closes nothing"},
      {"crystal.lattice=s\"c\",fcc", "value 1 of 2, s\"c\", is text with brackets or quotes in it"},
  };
  for (const auto& [option, what] : cases) {
    const std::string e = refusal({option});
    EXPECT_EQ(e.rfind("--vary '" + option + "': " + what, 0), 0u) << option << "\n" << e;
    EXPECT_NE(e.find("--vary 'loading.axis=[1,1,0],[1,1,1]'"), std::string::npos) << e;  // the example
  }
  const std::string twice = refusal({"material.friction=0.1", "material.friction=0.3"});
  EXPECT_NE(twice.find("'material.friction' is varied twice"), std::string::npos) << twice;
}

}  // namespace
