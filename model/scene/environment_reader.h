// Reads ORCS XML environments, format v1.0:
//
//   <ORCS version="1.0" [defaultRobot="true|false"]>
//     <Environment>
//       <object type="box|sphere" [name="..."] position="(x,y,z)" dimension="(w,h,d)|(r)" [orientation="(a,b,c)"]
//               [material="ABS"] [color="red|(r,g,b[,a])"] [texture="..."] [dynamic="true|false"] [mass="0.1"]/>
//     </Environment>
//     <Agent>
//       <ASeries name="Humanoid" [position="(x,y,z)"] [orientation="(a,b,c)"] [holdBody="..."] [file="robot.json"]/>
//     </Agent>
//   </ORCS>
//
// As in the original, the file's robots join the default A-Series "Humanoid" at the origin, unless the file names
// its own Humanoid, holds a <Pendulum> rig or says defaultRobot="false"; an object without a name is named after
// its type. Every problem is an InputError naming the file, the line and what was expected (docs/formats.md).
#pragma once

#include <string>

#include "model/scene/environment_description.h"

namespace orcs::scene {

class EnvironmentReader {
 public:
  /// Reads and checks an environment file; its robot files (<ASeries file="...">) are read relative to it.
  static EnvironmentDescription ReadFile(const std::string& file);
  /// Environment XML with every <ASeries file="robot.json"> replaced by the robot file's text inline
  /// (<ASeries><Morphology source="...">{...}</Morphology></ASeries>), read relative to `file`: what a job carries,
  /// so that a worker needs no file of the client's (docs/formats.md, "Robot files"). XML without robot files
  /// comes back as it was. Throws InputError naming the environment file and line for an unreadable robot file.
  static std::string InlineRobotFiles(const std::string& xml, const std::string& file);
  /// Reads and checks environment XML held in memory; `source` names it in messages.
  static EnvironmentDescription ReadString(const std::string& xml, const std::string& source);
  /// As ReadString, except that empty XML means the default environment: one A-Series on the floor (what
  /// orcs-sim runs without -env, and what a scenario or job without an environment gets).
  static EnvironmentDescription ReadStringOrDefault(const std::string& xml, const std::string& source);
};

}  // namespace orcs::scene
