#include <gtest/gtest.h>
#include <hymm/eval/MetricsJson.h>
#include <hymm/eval/metrics_report.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace
{
using hymm::eval::MetricsJson;

TEST(MetricsJsonTest, WritesNestedObjectsInInsertionOrder)
{
    MetricsJson j;
    j.set("name", "run 1").set("steps", 250).set("rmse", 0.125).set("ok", true);
    j.object("landmarks").set("matched", size_t{12}).set("errors", std::vector<double>{0.5, 1.0});
    j.set("tags", std::vector<std::string>{"a", "b"});
    j.setNull("missing");
    EXPECT_EQ(j.dump(0),
              "{\"name\":\"run 1\",\"steps\":250,\"rmse\":0.125,\"ok\":true,"
              "\"landmarks\":{\"matched\":12,\"errors\":[0.5,1]},\"tags\":[\"a\",\"b\"],"
              "\"missing\":null}");
    EXPECT_EQ(MetricsJson().dump(), "{}");
    MetricsJson small;
    small.set("a", 1).object("b").set("c", -2);
    EXPECT_EQ(small.dump(2), "{\n  \"a\": 1,\n  \"b\": {\n    \"c\": -2\n  }\n}");
}

TEST(MetricsJsonTest, ReplacingAKeyKeepsItsPosition)
{
    MetricsJson j;
    j.set("a", 1).set("b", 2).set("a", "x");
    EXPECT_EQ(j.dump(0), "{\"a\":\"x\",\"b\":2}");
    j.object("b").set("c", 3);
    j.object("b").set("d", 4);  // the same nested object, not a new one
    EXPECT_EQ(j.dump(0), "{\"a\":\"x\",\"b\":{\"c\":3,\"d\":4}}");
    EXPECT_EQ(j.size(), 2u);
}

TEST(MetricsJsonTest, EscapesStrings)
{
    EXPECT_EQ(MetricsJson::quote("a\"b\\c"), "\"a\\\"b\\\\c\"");
    EXPECT_EQ(MetricsJson::quote("l1\nl2\tx\r\b\f"), "\"l1\\nl2\\tx\\r\\b\\f\"");
    EXPECT_EQ(MetricsJson::quote(std::string("\x01\x1f", 2)), "\"\\u0001\\u001f\"");
    EXPECT_EQ(MetricsJson::quote("caf\xc3\xa9 /"), "\"caf\xc3\xa9 /\"");  // UTF-8 untouched
    MetricsJson j;
    j.set("we\"ird", "v");
    EXPECT_EQ(j.dump(0), "{\"we\\\"ird\":\"v\"}");
}

TEST(MetricsJsonTest, NumbersRoundTripAndNonFiniteBecomesNull)
{
    EXPECT_EQ(MetricsJson::number(0.1), "0.1");
    EXPECT_EQ(MetricsJson::number(-2.5e-8), "-2.5e-08");
    EXPECT_EQ(MetricsJson::number(std::numeric_limits<double>::quiet_NaN()), "null");
    EXPECT_EQ(MetricsJson::number(std::numeric_limits<double>::infinity()), "null");
    const double x = 1.0 / 3.0;
    EXPECT_EQ(std::stod(MetricsJson::number(x)), x);
    MetricsJson j;
    j.set("v", std::vector<double>{1.5, std::nan(""), -std::numeric_limits<double>::infinity()});
    j.set("big", 18446744073709551615ull).set("neg", -9223372036854775807ll);
    EXPECT_EQ(j.dump(0), "{\"v\":[1.5,null,null],\"big\":18446744073709551615,"
                         "\"neg\":-9223372036854775807}");
}

TEST(MetricsJsonTest, SavesToFile)
{
    const auto path = std::filesystem::temp_directory_path() / "hymm_metrics_json_test.json";
    MetricsJson j;
    j.set("k", 2);
    j.save(path.string(), 0);
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    EXPECT_EQ(ss.str(), "{\"k\":2}\n");
    std::filesystem::remove(path);
    EXPECT_THROW(j.save("/nonexistent/dir/m.json"), std::runtime_error);
}

TEST(MetricsJsonTest, ReportsUseDocumentedKeys)
{
    hymm::eval::TrajectoryEvaluator::Result t;
    t.matched = 3;
    t.position_rmse = 0.5;
    t.heading_rmse = 3.14159265358979323846 / 180.0;
    t.aligned = true;
    t.alignment = {1, 2, 0};
    MetricsJson j;
    hymm::eval::writeTrajectoryMetrics(j.object("trajectory"), t);
    const std::string s = j.dump(0);
    EXPECT_NE(s.find("\"matched\":3"), std::string::npos) << s;
    EXPECT_NE(s.find("\"position_rmse_m\":0.5"), std::string::npos) << s;
    EXPECT_NE(s.find("\"heading_rmse_deg\":1"), std::string::npos) << s;
    EXPECT_NE(s.find("\"alignment\":{\"x_m\":1,\"y_m\":2,\"phi_deg\":0}"), std::string::npos) << s;

    hymm::eval::LandmarkEvaluator::Result l;
    l.mean_nees = std::nan("");
    MetricsJson k;
    hymm::eval::writeLandmarkMetrics(k, l);
    EXPECT_NE(k.dump(0).find("\"mean_nees\":null"), std::string::npos);
}

}  // namespace
