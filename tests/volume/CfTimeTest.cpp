// CF time axes: units, reference dates and the CF calendars. Expected dates come from outside
// the code under test: GNU date / Python datetime for the standard (Gregorian) calendar, the
// calendar definitions of CF section 4.4.1 for the others (worked by hand in the comments).
#include <atmoglobe/volume/CfTime.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace atmoglobe::volume;

namespace {

std::string iso(const std::string& units, double value, const std::string& calendar = "") {
  auto t = parseCfTimeUnits(units, calendar);
  EXPECT_TRUE(t.ok()) << (t ? "" : t.error());
  if (!t) return "(error)";
  return cfTimeToIso8601(*t, value);
}

}  // namespace

TEST(CfTime, StandardCalendarMatchesGnuDate) {
  // `date -u -d @$((19000*86400))` -> 2022-01-08T00:00:00Z
  EXPECT_EQ(iso("days since 1970-01-01", 19000), "2022-01-08T00:00:00Z");
  // Python: datetime(2001,1,1) + timedelta(hours=36) -> 2001-01-02 12:00:00
  EXPECT_EQ(iso("hours since 2001-01-01 00:00:00", 36), "2001-01-02T12:00:00Z");
  // Python: datetime(1850,1,1) + timedelta(days=62000.25) -> 2019-10-02 06:00:00
  EXPECT_EQ(iso("days since 1850-01-01", 62000.25, "gregorian"), "2019-10-02T06:00:00Z");
  // WRF XTIME form, minutes.
  EXPECT_EQ(iso("minutes since 2005-08-28 00:00:00", 1260), "2005-08-28T21:00:00Z");
  EXPECT_EQ(iso("seconds since 1970-01-01T00:00:00Z", -1), "1969-12-31T23:59:59Z");
}

TEST(CfTime, CalendarsDifferWhereTheirDefinitionsSay) {
  // 2004 is a Gregorian leap year: day 59 after 1 January is 29 February...
  EXPECT_EQ(iso("days since 2004-01-01", 59, "standard"), "2004-02-29T00:00:00Z");
  // ...which noleap / 365_day skip (31 + 28 = 59 -> 1 March)...
  EXPECT_EQ(iso("days since 2004-01-01", 59, "noleap"), "2004-03-01T00:00:00Z");
  EXPECT_EQ(iso("days since 2004-01-01", 59, "365_day"), "2004-03-01T00:00:00Z");
  // ...all_leap keeps in every year (2001 too)...
  EXPECT_EQ(iso("days since 2001-01-01", 59, "all_leap"), "2001-02-29T00:00:00Z");
  // ...and 360_day months all have 30 days: day 59 is 30 February.
  EXPECT_EQ(iso("days since 2001-01-01", 59, "360_day"), "2001-02-30T00:00:00Z");
  EXPECT_EQ(iso("days since 2001-01-01", 360, "360_day"), "2002-01-01T00:00:00Z");
  // Julian: every fourth year is leap, 1900 included (not so in the Gregorian calendar).
  EXPECT_EQ(iso("days since 1900-02-28", 1, "julian"), "1900-02-29T00:00:00Z");
  EXPECT_EQ(iso("days since 1900-02-28", 1, "proleptic_gregorian"), "1900-03-01T00:00:00Z");
  // The standard calendar jumps from Julian 1582-10-04 to Gregorian 1582-10-15 (CF 4.4.1);
  // proleptic_gregorian has 1582-10-05 (Python's datetime is proleptic Gregorian).
  EXPECT_EQ(iso("days since 1582-10-04", 1, "standard"), "1582-10-15T00:00:00Z");
  EXPECT_EQ(iso("days since 1582-10-04", 1, "proleptic_gregorian"), "1582-10-05T00:00:00Z");
  // Backwards across the switch: one day before 1582-10-15 is 1582-10-04.
  EXPECT_EQ(iso("days since 1582-10-15", -1, "standard"), "1582-10-04T00:00:00Z");
}

TEST(CfTime, DayNumbersRoundTripInEveryCalendar) {
  for (CfCalendar c : {CfCalendar::Standard, CfCalendar::ProlepticGregorian, CfCalendar::Julian, CfCalendar::NoLeap,
                       CfCalendar::AllLeap, CfCalendar::Day360}) {
    std::int64_t previous = -1;
    for (int y : {1, 4, 99, 100, 400, 1581, 1582, 1583, 1900, 2000, 2001, 2024, 9999})
      for (int m = 1; m <= 12; ++m)
        for (int d = 1; d <= 31; ++d) {
          std::int64_t n = 0;
          if (!cfDayNumber(c, y, m, d, &n)) continue;
          int yy = 0, mm = 0, dd = 0;
          cfCalendarDate(c, n, &yy, &mm, &dd);
          ASSERT_EQ(yy * 10000 + mm * 100 + dd, y * 10000 + m * 100 + d) << toString(c) << " day " << n;
          ASSERT_GT(n, previous) << toString(c);  // days strictly increase
          previous = n;
        }
  }
  std::int64_t n = 0;
  EXPECT_FALSE(cfDayNumber(CfCalendar::Standard, 1582, 10, 10, &n)) << "a day that never happened";
  EXPECT_FALSE(cfDayNumber(CfCalendar::NoLeap, 2004, 2, 29, &n));
  EXPECT_TRUE(cfDayNumber(CfCalendar::Day360, 2001, 2, 30, &n));
  EXPECT_FALSE(cfDayNumber(CfCalendar::Day360, 2001, 1, 31, &n));
}

TEST(CfTime, ReferenceFormsAndZones) {
  EXPECT_EQ(iso("hours since 2001-1-1", 0), "2001-01-01T00:00:00Z");
  EXPECT_EQ(iso("hours since 2001-01-01T06:30", 0), "2001-01-01T06:30:00Z");
  EXPECT_EQ(iso("Hours Since 2001-01-01 00:00:00 UTC", 1), "2001-01-01T01:00:00Z");
  // Local time 00:00 at +02:00 is 22:00 UTC the day before.
  EXPECT_EQ(iso("hours since 2001-01-01 00:00:00 +02:00", 0), "2000-12-31T22:00:00Z");
  EXPECT_EQ(iso("hours since 2001-01-01 00:00:00 -0530", 0), "2001-01-01T05:30:00Z");
  // Fractions of a second add up before rounding: 0.5 + 0.4 s -> 1 s.
  EXPECT_EQ(iso("seconds since 2001-01-01 00:00:00.5", 0.4), "2001-01-01T00:00:01Z");
  auto t = parseCfTimeUnits("days since 2001-01-01", "");
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->calendar, CfCalendar::Standard) << "no calendar attribute means standard";
  EXPECT_EQ(cfTimeToIso8601(*t, std::nan("")), "") << "NaN time";
  EXPECT_EQ(cfTimeToIso8601(*t, 1e300), "") << "absurd time";
}

TEST(CfTime, BadUnitsAreErrorsThatSayWhy) {
  auto months = parseCfTimeUnits("months since 2001-01-01", "");
  ASSERT_FALSE(months.ok());
  EXPECT_NE(months.error().find("months"), std::string::npos) << months.error();
  auto unit = parseCfTimeUnits("fortnights since 2001-01-01", "");
  ASSERT_FALSE(unit.ok());
  EXPECT_NE(unit.error().find("fortnights"), std::string::npos) << unit.error();
  EXPECT_FALSE(parseCfTimeUnits("hours", "").ok());
  EXPECT_FALSE(parseCfTimeUnits("hours since yesterday", "").ok());
  EXPECT_FALSE(parseCfTimeUnits("hours since 2001-13-01", "").ok());
  EXPECT_FALSE(parseCfTimeUnits("days since 2001-02-30", "standard").ok()) << "no 30 February in the standard calendar";
  EXPECT_TRUE(parseCfTimeUnits("days since 2001-02-30", "360_day").ok());
  auto cal = parseCfTimeUnits("days since 2001-01-01", "martian");
  ASSERT_FALSE(cal.ok());
  EXPECT_NE(cal.error().find("martian"), std::string::npos) << cal.error();
}
