local t = 0
for i = 1, 200000 do
  local s = " " .. tostring(i * 3)
  t = t + tonumber(s) + #s
end
print(string.format("%.10g", t))
