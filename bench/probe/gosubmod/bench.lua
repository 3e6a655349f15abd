local s, f, c = 0, 0.0, 0
local function sub()
  if f > 50 then c = c + 1 end
end
for i = 1, 1000000 do
  s = (s + i * 1) % 1000003
  s = (s + i * 2) % 1000003
  s = (s + i * 3) % 1000003
  s = (s + i * 4) % 1000003
  s = (s + i * 5) % 1000003
  f = f * 0.9 + (s % 100) * 0.1
  sub()
end
print(s, string.format("%.7g", f), c)
