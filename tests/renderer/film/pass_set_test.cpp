#include "film/pass_set.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace caustic {

TEST(PassSet, JoinsAdjacentRangesAndCounts) {
    PassSet s;
    EXPECT_EQ(s.toString(), "none");
    EXPECT_TRUE(s.isPrefix());
    s.insert(4, 8);
    EXPECT_FALSE(s.isPrefix());
    s.insert(0, 2);
    s.insert(9, 10);
    EXPECT_EQ(s.toString(), "0-1,4-7,9");
    s.insert(2, 4);
    s.insert(8, 9);
    EXPECT_EQ(s.toString(), "0-9");
    EXPECT_EQ(s.count(), 10);
    EXPECT_EQ(s.end(), 10);
    EXPECT_TRUE(s.isPrefix());
    s.insert(5, 5);  // empty: nothing
    EXPECT_EQ(s.ranges().size(), 1u);
}

TEST(PassSet, RefusesOverlapsAndLeavesTheSetAsItWas) {
    PassSet s;
    s.insert(0, 4);
    s.insert(10, 12);
    EXPECT_THROW(s.insert(3, 5), std::invalid_argument);
    EXPECT_THROW(s.insert(11, 11 + 1), std::invalid_argument);
    EXPECT_THROW(s.insert(-1, 0), std::invalid_argument);
    PassSet other;
    other.insert(5, 6);
    other.insert(11, 20);
    EXPECT_THROW(s.insert(other), std::invalid_argument);
    EXPECT_EQ(s.toString(), "0-3,10-11");
    EXPECT_TRUE(s.overlaps(0, 1));
    EXPECT_FALSE(s.overlaps(4, 10));
}

}  // namespace caustic
