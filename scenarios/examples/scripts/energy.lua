-- The built-in "energy" term, written as a script (docs/extending.md): the work of every motor of the agent,
-- Σ over steps and motors of |torque · rate| · dt, J. Gives the built-in's value to the last bit: the same
-- numbers (the physics' own torque and rate) summed in the same order.
local motors = {}  -- handles: faster than names in the loop below
for i, name in ipairs(orcs.motors()) do motors[i] = orcs.motor(name) end
local torque, rate, abs = orcs.motor_torque, orcs.joint_rate, math.abs  -- locals: no table lookups per call
local joules = 0

function start()
  joules = 0
end

function step(dt)
  for i = 1, #motors do
    local motor = motors[i]
    joules = joules + abs(torque(motor) * rate(motor)) * dt
  end
end

function finish()
  return joules
end
