#include <gtest/gtest.h>
#include <hymm/ekf/StateLayout.h>

#include <stdexcept>

namespace
{
using hymm::ekf::StateLayout;

TEST(StateLayoutTest, BlocksOfDifferentSizesGetConsecutiveOffsets)
{
    StateLayout s;
    s.add(7, 2, 0);
    s.add(3, 3, 0);
    s.add(10, 2, 0);
    EXPECT_EQ(s.size(), 3u + 2u + 3u + 2u);
    EXPECT_EQ(s.get(7).offset, 3u);
    EXPECT_EQ(s.get(3).offset, 5u);
    EXPECT_EQ(s.get(10).offset, 8u);
    EXPECT_EQ(s.nextFreeId(), 11);
}

TEST(StateLayoutTest, RemovalShiftsLaterOffsetsAndKeepsIds)
{
    StateLayout s;
    s.add(1, 2, 0);
    s.add(2, 3, 0);
    s.add(3, 2, 0);
    const auto removed = s.remove(2);
    EXPECT_EQ(removed.offset, 5u);
    EXPECT_EQ(removed.dim, 3);
    EXPECT_FALSE(s.has(2));
    EXPECT_EQ(s.get(3).offset, 5u);
    EXPECT_EQ(s.get(1).offset, 3u);
    EXPECT_EQ(s.size(), 7u);
    EXPECT_EQ(s.ids(), (std::vector<long>{1, 3}));
}

TEST(StateLayoutTest, RejectsDuplicateNegativeAndUnknownIds)
{
    StateLayout s;
    s.add(1, 2, 0);
    EXPECT_THROW(s.add(1, 2, 0), std::invalid_argument);
    EXPECT_THROW(s.add(-1, 2, 0), std::invalid_argument);
    EXPECT_THROW(s.add(4, 0, 0), std::invalid_argument);
    EXPECT_THROW(s.remove(9), std::out_of_range);
    EXPECT_THROW(s.get(9), std::out_of_range);
}

}  // namespace
