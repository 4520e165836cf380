// The stress suite's table and CSV (bench/stress.h): RFC 4180 quoting of text fields, one CSV
// column per header field, and table rows whose columns line up under the header's.
#include "bench/stress.h"

#include <gtest/gtest.h>

#include <sstream>

namespace daisy {
namespace {

StressRow sampleRow() {
    StressRow row;
    row.name = "furnace rho=0.99";
    row.backend = "cpu";
    row.patches = 216;
    row.oracle = "B = E/(1-rho), bracket from row sums";
    row.error = 1.23456e-5;
    row.tolerance = 1e-3;
    row.status = "converged (12 it, residual 1e-10), said \"ok\"";
    row.seconds = 0.25;
    row.pass = true;
    return row;
}

TEST(StressCsv, QuotesTextFieldsAsRfc4180Says) {
    std::istringstream csv(stressCsv({sampleRow()}, "daisy bench --stress --quick"));
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "# daisy bench --stress --quick");
    std::getline(csv, line);
    EXPECT_EQ(line, "case,backend,patches,oracle,error,tolerance,finite,status,seconds,pass");
    std::getline(csv, line);
    // Commas put a field in quotes; a quote inside it is doubled. Numbers to 3 digits.
    EXPECT_EQ(line,
              "furnace rho=0.99,cpu,216,\"B = E/(1-rho), bracket from row sums\",1.23e-05,0.001,"
              "yes,\"converged (12 it, residual 1e-10), said \"\"ok\"\"\",0.25,PASS");
    EXPECT_FALSE(std::getline(csv, line));
}

TEST(StressTable, RowsLineUpUnderTheHeader) {
    const std::string header = stressTableHeader();
    StressRow failing = sampleRow();
    failing.pass = false;
    failing.finite = false;
    const std::string row = stressTableRow(failing);
    // Text columns are left-aligned (they start where the header's word starts), numbers
    // right-aligned (they end where it ends).
    for (const std::string column : {"backend", "finite", "oracle; status"}) {
        const std::size_t at = header.find(column);
        ASSERT_NE(at, std::string::npos) << column;
        EXPECT_NE(row[at], ' ') << column << "\n" << header << "\n" << row;
        EXPECT_EQ(row[at - 1], ' ') << column << "\n" << header << "\n" << row;
    }
    for (const std::string column : {"patches", "error", "tolerance", "time s"}) {
        const std::size_t end = header.find(column) + column.size() - 1;
        ASSERT_LT(end, header.size()) << column;
        EXPECT_NE(row[end], ' ') << column << "\n" << header << "\n" << row;
        EXPECT_EQ(row[end + 1], ' ') << column << "\n" << header << "\n" << row;
    }
    EXPECT_NE(row.find(" NO "), std::string::npos) << row;
    EXPECT_NE(row.find("FAIL"), std::string::npos) << row;
    EXPECT_NE(row.find("B = E/(1-rho), bracket from row sums; converged"), std::string::npos);
}

}  // namespace
}  // namespace daisy
