// Topology files: written by the simulator, read back strictly (the same format serves measurements).
#include "geartopo/grinding/topology_csv.hpp"

#include "grinding_fixture.hpp"

#include <sstream>

using namespace geartopo;

namespace {
std::string read_error(const std::string& text) {
  std::istringstream in(text);
  try {
    grinding::read_topology_csv(in, "m.csv", 35);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}
const std::string kHead = std::string(grinding::kTopologyHeader) + "\n";
} // namespace

TEST(TopologyCsv, WrittenGridReadsBack) {
  const auto model = test::machine_with({machine::ErrorSource::constant(machine::ComponentId::delta_zz, 10.0, "um")});
  const grinding::MachineProcess process(model, test::kDatumZ);
  const auto topo = test::simulate(process, grinding::Method::Linear);
  std::stringstream buf;
  grinding::write_topology_csv(buf, topo);
  const auto rows = grinding::read_topology_csv(buf, "mem", 35);
  const auto expected = grinding::topology_rows(topo);
  ASSERT_EQ(rows.size(), 4u * 63u);
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].tooth, expected[i].tooth);
    EXPECT_EQ(rows[i].flank, expected[i].flank);
    EXPECT_EQ(rows[i].row, expected[i].row);
    EXPECT_EQ(rows[i].col, expected[i].col);
    EXPECT_NEAR(rows[i].deviation_um, expected[i].deviation_um, 5e-5);
    EXPECT_NEAR(rows[i].z_mm, expected[i].z_mm, 5e-5);
  }
  // Rows from root to tip, columns from the datum face.
  EXPECT_LT(rows[0].diameter_mm, rows[9].diameter_mm);
  EXPECT_LT(rows[0].z_mm, rows[1].z_mm);
}

TEST(TopologyCsv, BadFilesNameLineColumnAndField) {
  EXPECT_EQ(read_error("tooth,flank,row\n"),
            "m.csv:1:16: header: expected the columns tooth,flank,row,col,diameter_mm,z_mm,deviation_um[,design_um] (column 4 "
            "should be 'col')");
  EXPECT_EQ(read_error(kHead + "1,middle,1,1,550,7.5,0.1\n"), "m.csv:2:3: flank: 'middle' is neither left nor right");
  EXPECT_EQ(read_error(kHead + "36,left,1,1,550,7.5,0.1\n"), "m.csv:2:1: tooth: 36 is not one of 1..35");
  EXPECT_EQ(read_error(kHead + "1,left,1,1,550,7.5,nan\n"), "m.csv:2:20: deviation_um: 'nan' is not finite");
  EXPECT_EQ(read_error(kHead + "1,left,1,1,550,x,0.1\n"), "m.csv:2:16: z_mm: 'x' is not a number");
  EXPECT_EQ(read_error(kHead + "1,left,1,1,550,7.5\n"), "m.csv:2:19: row: 6 fields, expected 7");
  EXPECT_EQ(read_error(kHead + "1,left,1,1,550,7.5,0.1\n1,left,1,1,551,7.5,0.2\n"),
            "m.csv:3:1: row: duplicate point: tooth 1 left row 1 col 1");
  EXPECT_EQ(read_error(kHead), "m.csv:1:1: rows: no data rows");
  EXPECT_EQ(read_error(""), "m.csv:1:1: header: missing header tooth,flank,row,col,diameter_mm,z_mm,deviation_um");
}

// The design column (issue 26): optional, read when the header names it, checked like a deviation; a file without it
// has design 0 (measured against the bare involute).
TEST(TopologyCsv, TheDesignColumnIsOptionalAndChecked) {
  const std::string with = std::string(grinding::kTopologyHeader) + "," + grinding::kDesignColumn + "\n";
  std::istringstream in(with + "1,left,1,1,560.5,10,0.25,-3.5\n");
  const auto rows = grinding::read_topology_csv(in, "m.csv", 35);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].design_um, -3.5);
  std::istringstream plain(kHead + "1,left,1,1,560.5,10,0.25\n");
  EXPECT_EQ(grinding::read_topology_csv(plain, "m.csv", 35)[0].design_um, 0.0);
  EXPECT_EQ(read_error(with + "1,left,1,1,560.5,10,0.25,nan\n"), "m.csv:2:26: design_um: 'nan' is not finite");
  EXPECT_EQ(read_error(with + "1,left,1,1,560.5,10,0.25\n"), "m.csv:2:25: row: 7 fields, expected 8");
  EXPECT_EQ(read_error(kHead + "1,left,1,1,560.5,10,0.25,1\n"), "m.csv:2:26: row: 8 fields, expected 7");
  EXPECT_EQ(read_error(std::string(grinding::kTopologyHeader) + ",design_mm\n"),
            "m.csv:1:51: header: unexpected column 'design_mm' (the only column after deviation_um is design_um)");
  EXPECT_EQ(read_error(with + "1,left,1,1,560.5,10,0.25,2e6\n"),
            "m.csv:2:26: design_um: 2e6 µm is beyond ±1000 µm, more than a drawing modifies a flank (a wrong unit?)");
}
