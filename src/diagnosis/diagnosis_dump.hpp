// geartopo diagnosis, private — the golden set of diagnoses (docs/diagnosis.md, "The golden set"): with the
// environment variable GEARTOPO_DIAGNOSIS_DUMP naming a folder, every diagnose() writes its diagnosis.json there, named
// after the test that ran it (pytest's PYTEST_CURRENT_TEST, or the --gtest_filter of this process or its parent: ctest
// runs one test per process and the CLI tests start geartopo from theirs), the program's arguments and a count. A
// developer tool for refactoring diagnose: scripts/diagnosis-golden.sh captures the set before and after a change and
// compares the two. Off (one getenv per diagnosis) unless the variable is set.
#pragma once

#include "geartopo/diagnosis/diagnose.hpp"

namespace geartopo::diagnosis {

void dump_if_asked(const Diagnosis& d);

} // namespace geartopo::diagnosis
