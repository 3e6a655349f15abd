local s, t, c = 0.0, 0.0, 0
for i = 1, 1000000 do
  local x = (i % 2001 - 1000) / 7
  local fix = x >= 0 and math.floor(x) or math.ceil(x)
  s = s + math.abs(x) + math.floor(x) - fix
  if x < 0 then c = c + 1 end
  t = t + math.sqrt(math.abs(x))
end
print(c, string.format("%.10g", s), string.format("%.10g", t))
