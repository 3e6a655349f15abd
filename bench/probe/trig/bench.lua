local x, v, dt, e = 0.5, 0, 0.0001, 0
for i = 1, 1000000 do
  local a = -9.81 * math.sin(x)
  v = v + a * dt
  x = x + v * dt
  e = e + math.sqrt(v * v + 1) * math.cos(x)
end
print(string.format("%.10g %.10g", x + 1, e))
