#pragma once
// CF time coordinates: "UNIT since REFERENCE" in one of the CF calendars, to ISO 8601 UTC.
//
// CF conventions (section 4.4, "Time coordinate"): a time value counts UNITs (seconds, minutes,
// hours or days; months and years are refused, CF itself discourages them because their length
// varies) after a reference date-time, in the calendar named by the `calendar` attribute:
//   standard / gregorian (the default): the mixed Julian/Gregorian calendar, Julian up to
//     1582-10-04, Gregorian from 1582-10-15;
//   proleptic_gregorian; julian; noleap / 365_day; all_leap / 366_day; 360_day (twelve months
//   of 30 days).
// A date of a non-standard calendar is written as that calendar names it (a 360_day file can
// hold 2001-02-30), so the text is a label, not a point on the real time line.
//
// Reference forms accepted: "YYYY-M-D", then optionally 'T' or blanks and "h:m", ":s", ".frac",
// then optionally "Z", "UTC", "GMT" or an offset "+hh", "+hh:mm", "-hhmm" (subtracted to give
// UTC). Years 1..9999. Results are rounded to the nearest second.
#include <atmoglobe/globe/Result.h>

#include <cstdint>
#include <string>

namespace atmoglobe::volume {

enum class CfCalendar { Standard, ProlepticGregorian, Julian, NoLeap, AllLeap, Day360 };

/// The calendar's CF name ("standard", "proleptic_gregorian", "julian", "noleap", "all_leap", "360_day").
const char* toString(CfCalendar c);

/// Parses a `calendar` attribute (case-insensitive; empty means "standard"). Error text (no file
/// name): "calendar 'X' is not a CF calendar".
Result<CfCalendar> parseCfCalendar(const std::string& name);

/// A parsed time axis: value v means reference + v * secondsPerUnit seconds.
struct CfTimeUnits {
  double secondsPerUnit = 1.0;
  CfCalendar calendar = CfCalendar::Standard;
  /// The reference, as a second count in the calendar's own day numbering (UTC).
  std::int64_t referenceSeconds = 0;
  double referenceFractionSeconds = 0.0;  ///< fraction of a second of the reference, [0, 1)
  std::string unitName;                   ///< "seconds", "minutes", "hours" or "days"
  std::string referenceIso8601;           ///< the reference, normalised (UTC)
};

/// Parses `units` ("hours since 2001-01-01 00:00:00") with `calendar` (the attribute's text,
/// empty for none). Error text (no file name): what part of the units is wrong.
Result<CfTimeUnits> parseCfTimeUnits(const std::string& units, const std::string& calendar);

/// ISO 8601 UTC text "YYYY-MM-DDTHH:MM:SSZ" of `value` on the axis, rounded to the second.
/// Empty if `value` is not finite or the date falls outside years 1..9999.
std::string cfTimeToIso8601(const CfTimeUnits& units, double value);

/// Day number of a calendar date (day 0 = 0001-01-01 of the calendar for every calendar but the
/// standard one, whose numbering is the Julian day number minus 1721424, so that its day 0 is
/// 0001-01-01 Julian). False when the date does not exist in the calendar (month 13, Feb 30 in
/// a Gregorian year, 1582-10-10 in the standard calendar...).
bool cfDayNumber(CfCalendar calendar, int year, int month, int day, std::int64_t* dayNumber);

/// Inverse of cfDayNumber.
void cfCalendarDate(CfCalendar calendar, std::int64_t dayNumber, int* year, int* month, int* day);

}  // namespace atmoglobe::volume
