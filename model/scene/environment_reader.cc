#include "model/scene/environment_reader.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "model/aseries/aseries_morphology.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/core/text_file.h"

namespace orcs::scene {
namespace {

namespace fs = std::filesystem;

using tinyxml2::XMLElement;

constexpr std::string_view kFormatVersion = "1.0";

// Levels of nested elements an environment may have (the root is level 1; the format itself needs 3). tinyxml2
// refuses deeper nesting on its own (TINYXML2_MAX_ELEMENT_DEPTH, 100 in Debian's 9.0, so that its recursive parser
// cannot overflow the stack); below that, the reader enforces this documented bound (docs/formats.md, "Input
// limits"), so the message and the limit do not depend on the tinyxml2 version.
constexpr int kMaxElementDepth = 32;
static_assert(kMaxElementDepth < TINYXML2_MAX_ELEMENT_DEPTH, "tinyxml2 must not refuse nesting within our bound");

std::string TooDeep() { return "XML elements nested deeper than " + std::to_string(kMaxElementDepth) + " levels"; }

// The first element below `root` deeper than kMaxElementDepth, or nullptr; walks without recursion.
const XMLElement* TooDeepElement(const XMLElement& root) {
  const XMLElement* element = &root;
  int depth = 1;
  while (element != nullptr) {
    if (depth > kMaxElementDepth) return element;
    if (const XMLElement* child = element->FirstChildElement()) {
      element = child;
      ++depth;
      continue;
    }
    while (element != nullptr && element != &root && element->NextSiblingElement() == nullptr) {
      element = element->Parent()->ToElement();
      --depth;
    }
    element = element == nullptr || element == &root ? nullptr : element->NextSiblingElement();
  }
  return nullptr;
}

// Attribute access for one element, with every error naming file, line, element and attribute.
class ElementReader {
 public:
  ElementReader(const XMLElement& element, const std::string& source, std::set<std::string_view> allowed)
      : element_(element), source_(source) {
    for (const tinyxml2::XMLAttribute* a = element.FirstAttribute(); a != nullptr; a = a->Next()) {
      if (!allowed.contains(a->Name())) {
        Fail("unknown attribute " + text::Quote(a->Name()) + " (expected one of " + List(allowed) + ")");
      }
    }
  }

  int line() const { return element_.GetLineNum(); }
  bool Has(const char* name) const { return element_.Attribute(name) != nullptr; }

  std::string String(const char* name, const std::string& fallback) const {
    const char* value = element_.Attribute(name);
    return value == nullptr ? fallback : std::string(text::Trim(value));
  }

  std::string RequiredString(const char* name) const {
    if (!Has(name)) Fail("missing mandatory attribute " + text::Quote(std::string(name)));
    const std::string value = String(name, "");
    if (value.empty()) Fail("attribute " + text::Quote(std::string(name)) + " is empty");
    return value;
  }

  std::vector<double> Tuple(const char* name, size_t min_count, size_t max_count) const {
    const std::string value = String(name, "");
    const auto numbers = text::ParseNumberTuple(value);
    // Positions, angles and sizes must be finite: "inf" parses as a number but would reach the physics engine.
    const bool finite =
        numbers && std::all_of(numbers->begin(), numbers->end(), [](double x) { return std::isfinite(x); });
    if (!finite || numbers->size() < min_count || numbers->size() > max_count) {
      const std::string expected = min_count == max_count ? std::to_string(min_count) + " numbers"
                                                          : std::to_string(min_count) + " to " +
                                                                std::to_string(max_count) + " numbers";
      Fail("attribute " + text::Quote(std::string(name)) + " expected " + expected + " like (1,2,3), found " +
           text::Quote(value));
    }
    return *numbers;
  }

  Eigen::Vector3d Vector(const char* name, const Eigen::Vector3d& fallback) const {
    if (!Has(name)) return fallback;
    const std::vector<double> v = Tuple(name, 3, 3);
    return {v[0], v[1], v[2]};
  }

  double PositiveNumber(const char* name) const {
    const std::string value = String(name, "");
    const auto number = text::ParseDouble(value);
    if (!number || !(*number > 0) || std::isinf(*number)) {
      Fail("attribute " + text::Quote(std::string(name)) + " expected a positive number, found " + text::Quote(value));
    }
    return *number;
  }

  bool Bool(const char* name, bool fallback) const {
    if (!Has(name)) return fallback;
    const std::string value = String(name, "");
    for (std::string_view yes : {"true", "T", "1"})
      if (text::EqualsIgnoreCase(value, yes)) return true;
    for (std::string_view no : {"false", "F", "0"})
      if (text::EqualsIgnoreCase(value, no)) return false;
    Fail("attribute " + text::Quote(std::string(name)) + " expected true or false, found " + text::Quote(value));
  }

  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(source_, line(), "<" + std::string(element_.Name()) + ">" + Subject() + ": " + what);
  }

 private:
  std::string Subject() const {
    const char* name = element_.Attribute("name");
    return name == nullptr ? "" : " " + text::Quote(std::string(name));
  }

  static std::string List(const std::set<std::string_view>& names) {
    std::string list;
    for (std::string_view name : names) list += (list.empty() ? "" : ", ") + std::string(name);
    return list;
  }

  const XMLElement& element_;
  const std::string& source_;
};

// A name becomes a repository path segment (/Sim/<name>/...): no white space, no leading or trailing '/'.
void CheckName(const ElementReader& reader, const std::string& name) {
  const bool bad_slash = name.front() == '/' || name.back() == '/' || name.find("//") != std::string::npos;
  if (bad_slash || name.find_first_of(" \t\r\n") != std::string::npos) {
    reader.Fail("attribute 'name' expected a name without spaces or leading/trailing '/', found " +
                text::Quote(name));
  }
}

ObjectDescription ReadObject(const XMLElement& element, const std::string& source) {
  const ElementReader reader(element, source,
                            {"type", "name", "position", "orientation", "dimension", "material", "color",
                             "texture", "dynamic", "mass"});
  ObjectDescription object;
  object.line = reader.line();
  // The original named an object without `name` after its type ("box", "sphere"): NameUnnamedObjects().
  if (reader.Has("name")) {
    object.name = reader.RequiredString("name");
    CheckName(reader, object.name);
  }
  const std::string type = reader.RequiredString("type");
  if (text::EqualsIgnoreCase(type, "box")) {
    object.type = ObjectType::kBox;
  } else if (text::EqualsIgnoreCase(type, "sphere")) {
    object.type = ObjectType::kSphere;
  } else {
    reader.Fail("attribute 'type' expected box or sphere, found " + text::Quote(type));
  }
  reader.RequiredString("position");
  object.position = reader.Vector("position", Eigen::Vector3d::Zero());
  object.orientation = reader.Vector("orientation", Eigen::Vector3d::Zero());
  reader.RequiredString("dimension");
  if (object.type == ObjectType::kBox) {
    const std::vector<double> size = reader.Tuple("dimension", 3, 3);
    object.dimension = {size[0], size[1], size[2]};
  } else {
    object.dimension = {reader.Tuple("dimension", 1, 1)[0], 0.0, 0.0};
  }
  if (object.dimension.x() <= 0 || (object.type == ObjectType::kBox && object.dimension.minCoeff() <= 0)) {
    reader.Fail("attribute 'dimension' expected positive sizes, found " +
                text::Quote(reader.String("dimension", "")));
  }
  object.material = reader.String("material", object.material);
  object.texture = reader.String("texture", "");
  if (reader.Has("color")) {
    const auto color = ParseColor(reader.String("color", ""));
    if (!color) {
      reader.Fail("attribute 'color' expected a colour name or (r,g,b[,a]) with channels 0..255, found " +
                  text::Quote(reader.String("color", "")));
    }
    object.color = *color;
  }
  object.dynamic = reader.Bool("dynamic", false);
  if (object.dynamic && !reader.Has("mass")) reader.Fail("a dynamic object needs attribute 'mass'");
  if (reader.Has("mass")) object.mass = reader.PositiveNumber("mass");
  return object;
}

[[noreturn]] void FailAt(const std::string& source, const XMLElement& element, const std::string& what) {
  throw InputError(source, element.GetLineNum(), what);
}

// An <ASeries>'s robot from its <Morphology> child (a robot file inlined: InlineRobotFiles), or null for the
// built-in A-Series. The robot file's errors name the file and the field (ParseASeriesMorphology).
std::shared_ptr<const aseries::ASeriesMorphology> ReadMorphology(const XMLElement& element, const ElementReader& reader,
                                                                 const std::string& source, std::string& robot_source) {
  if (reader.Has("file")) {
    reader.Fail("attribute 'file' names a robot file relative to the environment's file, and this environment has "
                "none: read it from its file (-env), or put the robot inline as a <Morphology> child");
  }
  const XMLElement* inline_robot = nullptr;
  for (const XMLElement* child = element.FirstChildElement(); child; child = child->NextSiblingElement()) {
    if (std::string_view(child->Name()) != "Morphology" || inline_robot != nullptr) {
      FailAt(source, *child, "unexpected element <" + std::string(child->Name()) + "> in <ASeries> (expected at most one <Morphology>)");
    }
    inline_robot = child;
  }
  if (inline_robot == nullptr) return nullptr;
  const ElementReader morphology(*inline_robot, source, {"source"});
  robot_source = morphology.String("source", source + ":" + std::to_string(inline_robot->GetLineNum()));
  const char* json = inline_robot->GetText();
  return std::make_shared<const aseries::ASeriesMorphology>(
      aseries::ParseASeriesMorphology(json == nullptr ? "" : json, robot_source));
}

AgentDescription ReadAgent(const XMLElement& element, const std::string& source) {
  const bool pendulum = std::string_view(element.Name()) == "Pendulum";
  const ElementReader reader(element, source,
                             pendulum ? std::set<std::string_view>{"name", "position", "orientation", "poleMass",
                                                                   "poleLength"}
                                      : std::set<std::string_view>{"name", "position", "orientation", "holdBody",
                                                                   "file"});
  AgentDescription agent;
  agent.line = reader.line();
  agent.type = element.Name();
  agent.name = reader.String("name", pendulum ? "Pendulum" : agent.name);
  if (agent.name.empty()) reader.Fail("attribute 'name' is empty");
  CheckName(reader, agent.name);
  agent.position = reader.Vector("position", Eigen::Vector3d::Zero());
  agent.orientation = reader.Vector("orientation", Eigen::Vector3d::Zero());
  if (pendulum) {
    if (reader.Has("poleMass")) agent.pole_mass = reader.PositiveNumber("poleMass");
    if (reader.Has("poleLength")) agent.pole_length = reader.PositiveNumber("poleLength");
    return agent;
  }
  agent.morphology = ReadMorphology(element, reader, source, agent.morphology_source);
  if (reader.Has("holdBody")) {
    agent.hold_body = reader.RequiredString("holdBody");
    const aseries::ASeriesMorphology& robot = agent.morphology ? *agent.morphology : aseries::DefaultASeriesMorphology();
    if (robot.FindBody(agent.hold_body) < 0) {
      reader.Fail("attribute 'holdBody' expected a body of the robot like \"" + robot.root_body + "\", found " +
                  text::Quote(agent.hold_body));
    }
  }
  return agent;
}

void ReadEnvironment(const XMLElement& section, const std::string& source, EnvironmentDescription& out) {
  ElementReader(section, source, {});
  for (const XMLElement* child = section.FirstChildElement(); child; child = child->NextSiblingElement()) {
    if (std::string_view(child->Name()) != "object") {
      FailAt(source, *child, "unknown element <" + std::string(child->Name()) + "> in <Environment> (expected <object>)");
    }
    out.objects.push_back(ReadObject(*child, source));
  }
}

void ReadAgents(const XMLElement& section, const std::string& source, EnvironmentDescription& out) {
  ElementReader(section, source, {});
  for (const XMLElement* child = section.FirstChildElement(); child; child = child->NextSiblingElement()) {
    const std::string_view type = child->Name();
    if (type != "ASeries" && type != "Pendulum") {
      FailAt(source, *child,
             "unknown agent type <" + std::string(type) + "> (expected <ASeries> or <Pendulum>)");
    }
    out.agents.push_back(ReadAgent(*child, source));
  }
}

// An object without a name gets its type's, as in the original ("box", "sphere"); a second one of the type
// "box_2", and so on, since names are repository paths and must differ (docs/formats.md).
void NameUnnamedObjects(EnvironmentDescription& environment) {
  std::set<std::string> taken{"Floor"};
  for (const ObjectDescription& object : environment.objects) taken.insert(object.name);
  for (const AgentDescription& agent : environment.agents) taken.insert(agent.name);
  for (ObjectDescription& object : environment.objects) {
    if (!object.name.empty()) continue;
    const std::string base = object.type == ObjectType::kBox ? "box" : "sphere";
    object.name = base;
    for (int n = 2; taken.count(object.name) != 0; ++n) object.name = base + "_" + std::to_string(n);
    taken.insert(object.name);
  }
}

// The original added a file's robots to its default A-Series, "Humanoid" at the origin. So does orcs, unless the
// file names its own Humanoid (which takes the default's place), holds a rig (<Pendulum>, an orcs addition: a rig
// experiment stands alone), or says defaultRobot="false" (docs/formats.md, "The default robot").
void AddDefaultRobot(EnvironmentDescription& environment, std::optional<bool> wanted) {
  const AgentDescription robot;
  bool named = false, rig = false;
  for (const AgentDescription& agent : environment.agents) {
    named = named || agent.name == robot.name;
    rig = rig || agent.type == "Pendulum";
  }
  if (named || !wanted.value_or(!rig)) return;
  environment.agents.insert(environment.agents.begin(), robot);
}

// Object and agent names share one namespace (/Sim/<name>/...); "Floor" is taken by the floor plane.
void CheckUniqueNames(const EnvironmentDescription& environment) {
  std::set<std::string> names{"Floor"};
  const auto claim = [&](const std::string& name, int line) {
    if (!names.insert(name).second) {
      throw InputError(environment.source, line, "name " + text::Quote(name) + " is used twice (or is reserved)");
    }
  };
  for (const ObjectDescription& object : environment.objects) claim(object.name, object.line);
  for (const AgentDescription& agent : environment.agents) claim(agent.name, agent.line);
}

}  // namespace

EnvironmentDescription EnvironmentReader::ReadStringOrDefault(const std::string& xml, const std::string& source) {
  if (!xml.empty()) return ReadString(xml, source);
  EnvironmentDescription environment;
  environment.source = source;
  environment.agents.push_back(AgentDescription{});
  return environment;
}

EnvironmentDescription EnvironmentReader::ReadString(const std::string& xml, const std::string& source) {
  tinyxml2::XMLDocument document;
  const tinyxml2::XMLError parsed = document.Parse(xml.c_str(), xml.size());
  if (parsed == tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED) throw InputError(source, document.ErrorLineNum(), TooDeep());
  if (parsed != tinyxml2::XML_SUCCESS) {
    throw InputError(source, document.ErrorLineNum(), std::string("malformed XML: ") + document.ErrorStr());
  }
  const XMLElement* root = document.RootElement();
  if (root == nullptr) throw InputError(source, 0, "expected an <ORCS> element, found none");
  if (const XMLElement* deep = TooDeepElement(*root)) FailAt(source, *deep, TooDeep());
  if (std::string_view(root->Name()) != "ORCS") {
    FailAt(source, *root, "expected root element <ORCS>, found <" + std::string(root->Name()) + ">");
  }
  const ElementReader root_reader(*root, source, {"version", "defaultRobot"});
  const std::string version = root_reader.String("version", "");
  if (version != kFormatVersion) {
    root_reader.Fail("attribute 'version' expected \"1.0\", found " + text::Quote(version));
  }
  EnvironmentDescription environment;
  environment.source = source;
  for (const XMLElement* section = root->FirstChildElement(); section; section = section->NextSiblingElement()) {
    const std::string_view name = section->Name();
    if (name == "Environment") {
      ReadEnvironment(*section, source, environment);
    } else if (name == "Agent") {
      ReadAgents(*section, source, environment);
    } else {
      FailAt(source, *section, "unknown element <" + std::string(name) + "> (expected <Environment> or <Agent>)");
    }
  }
  AddDefaultRobot(environment, root_reader.Has("defaultRobot")
                                   ? std::optional<bool>(root_reader.Bool("defaultRobot", true))
                                   : std::nullopt);
  NameUnnamedObjects(environment);
  CheckUniqueNames(environment);
  return environment;
}

EnvironmentDescription EnvironmentReader::ReadFile(const std::string& file) {
  return ReadString(InlineRobotFiles(ReadTextFile(file), file), file);
}

std::string EnvironmentReader::InlineRobotFiles(const std::string& xml, const std::string& file) {
  tinyxml2::XMLDocument document;
  if (document.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS || document.RootElement() == nullptr) {
    return xml;  // ReadString says what is wrong
  }
  bool inlined = false;
  const fs::path folder = fs::path(file).parent_path();
  for (XMLElement* section = document.RootElement()->FirstChildElement("Agent"); section;
       section = section->NextSiblingElement("Agent")) {
    for (XMLElement* robot = section->FirstChildElement("ASeries"); robot; robot = robot->NextSiblingElement("ASeries")) {
      const char* name = robot->Attribute("file");
      if (name == nullptr) continue;
      const fs::path path = fs::path(name).is_absolute() ? fs::path(name) : folder / name;
      std::string json;
      try {
        json = ReadTextFile(path.string());
      } catch (const InputError& error) {
        throw InputError(file, robot->GetLineNum(), "attribute 'file' expected a readable robot file, found " +
                                                        text::Quote(path.string()) + ": " + error.what());
      }
      XMLElement* morphology = document.NewElement("Morphology");
      morphology->SetAttribute("source", path.lexically_normal().string().c_str());
      morphology->SetText(json.c_str());
      robot->InsertFirstChild(morphology);
      robot->DeleteAttribute("file");
      inlined = true;
    }
  }
  if (!inlined) return xml;  // the text exactly as written
  tinyxml2::XMLPrinter printer;
  document.Print(&printer);
  return printer.CStr();
}

}  // namespace orcs::scene
